"""Shipped solutions of 06-pose-a (pinned checksums and golden quick scores)."""

from rle_tasks.core.solutions import SolutionSet
from rle_tasks.f06_pose_estimation.solutions import PACKAGE, estimator_solutions

PINS = {
    "reference": ("b8c209d94c1214d82a794707846514daca41dd33a7307d595d9f0b975b918d84", 0.679499),
    "baseline/wrong_shape": ("058e3cbd731dc15fb04d22191edda1abb0acbf30b05186b975ad758cfac8cf65", 0.0),
}
SOLUTIONS = SolutionSet(package=PACKAGE, solutions=estimator_solutions(PINS))
