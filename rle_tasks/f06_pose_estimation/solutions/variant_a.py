"""Shipped solutions of 06-pose-a (pinned checksums and golden quick scores)."""

from rle_tasks.core.solutions import SolutionSet
from rle_tasks.f06_pose_estimation.solutions import PACKAGE, estimator_solutions

PINS = {
    "reference": ("5d6770af43598c5384245bd4f14ee156e0da7a22c09c684c4bf63b62d243239d", 0.884681),
    "baseline/wrong_shape": ("10d369eb1ac2e5e29a07551df73a8575c4b8a0716a563b8448d18f60367deac1", 0.0),
}
SOLUTIONS = SolutionSet(package=PACKAGE, solutions=estimator_solutions(PINS))
