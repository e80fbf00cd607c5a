"""Shipped solutions of 06-pose-b (pinned checksums and golden quick scores)."""

from rle_tasks.core.solutions import SolutionSet
from rle_tasks.f06_pose_estimation.solutions import PACKAGE, estimator_solutions

PINS = {
    "reference": ("b8c209d94c1214d82a794707846514daca41dd33a7307d595d9f0b975b918d84", 0.908352),
    "baseline/wrong_shape": ("058e3cbd731dc15fb04d22191edda1abb0acbf30b05186b975ad758cfac8cf65", 0.0),
    "baseline/nan_output": ("3a317c1a9c4f032a83446b2f5be784018d16cedcf28665e56ebe15d0f563d4c1", 0.0),
    "baseline/hang": ("f74148c1d72b95fcb5399759b4c914b6202710b39c5e10196d673d812b08ccd4", 0.0),
    "baseline/slow": ("f8ce59201183a1c43272ed8246a8506c80d18516fb3f50ff31759479cc190a10", 0.779283),
}
SOLUTIONS = SolutionSet(package=PACKAGE, solutions=estimator_solutions(PINS))
