"""Shipped solutions of 06-pose-d (pinned checksums and golden quick scores)."""

from rle_tasks.core.solutions import SolutionSet
from rle_tasks.f06_pose_estimation.solutions import PACKAGE, estimator_solutions

PINS = {
    "reference": ("5d6770af43598c5384245bd4f14ee156e0da7a22c09c684c4bf63b62d243239d", 0.902788),
    "baseline/nan_output": ("3a317c1a9c4f032a83446b2f5be784018d16cedcf28665e56ebe15d0f563d4c1", 0.0),
}
SOLUTIONS = SolutionSet(package=PACKAGE, solutions=estimator_solutions(PINS))
