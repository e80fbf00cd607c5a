"""Shipped solutions of 06-pose-a (pinned checksums and golden quick scores)."""

from rle_tasks.core.solutions import SolutionSet
from rle_tasks.f06_pose_estimation.solutions import PACKAGE, estimator_solutions

PINS = {
    "reference": ("0" * 64, 0.0),
    "baseline/wrong_shape": ("0" * 64, 0.0),
    "baseline/nan_output": ("0" * 64, 0.0),
    "baseline/hang": ("0" * 64, 0.0),
    "baseline/slow": ("0" * 64, 0.0),
}
SOLUTIONS = SolutionSet(package=PACKAGE, solutions=estimator_solutions(PINS))
