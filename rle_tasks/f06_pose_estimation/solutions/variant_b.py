"""Shipped solutions of 06-pose-b (pinned checksums and golden quick scores)."""

from rle_tasks.core.solutions import SolutionSet
from rle_tasks.f06_pose_estimation.solutions import PACKAGE, estimator_solutions

PINS = {
    "reference": ("5d6770af43598c5384245bd4f14ee156e0da7a22c09c684c4bf63b62d243239d", 0.902788),
    "baseline/wrong_shape": ("10d369eb1ac2e5e29a07551df73a8575c4b8a0716a563b8448d18f60367deac1", 0.0),
    "baseline/nan_output": ("3a317c1a9c4f032a83446b2f5be784018d16cedcf28665e56ebe15d0f563d4c1", 0.0),
    "baseline/hang": ("f74148c1d72b95fcb5399759b4c914b6202710b39c5e10196d673d812b08ccd4", 0.0),
    "baseline/slow": ("0769b2d684e75efdfa274f2554e5de78d310efb4f03713893c08bece6a4af3ed", 0.72501),
}
SOLUTIONS = SolutionSet(package=PACKAGE, solutions=estimator_solutions(PINS))
