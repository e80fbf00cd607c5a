"""Shipped solutions of 06-pose-d (pinned checksums and golden quick scores)."""

from rle_tasks.core.solutions import SolutionSet
from rle_tasks.f06_pose_estimation.solutions import PACKAGE, estimator_solutions

PINS = {
    "reference": ("b8c209d94c1214d82a794707846514daca41dd33a7307d595d9f0b975b918d84", 0.908352),
    "baseline/nan_output": ("3a317c1a9c4f032a83446b2f5be784018d16cedcf28665e56ebe15d0f563d4c1", 0.0),
}
SOLUTIONS = SolutionSet(package=PACKAGE, solutions=estimator_solutions(PINS))
