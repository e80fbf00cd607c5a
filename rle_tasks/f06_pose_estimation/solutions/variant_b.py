"""Shipped solutions of 06-pose-b (pinned checksums and golden quick scores)."""

from rle_tasks.core.solutions import SolutionSet
from rle_tasks.f06_pose_estimation.solutions import PACKAGE, estimator_solutions

PINS = {
    "reference": ("85bff44e304af3a2419fd5a08bc74159672502aa9f2585649efbb2ebed9f1eb4", 0.0),
    "baseline/wrong_shape": ("9252e68d046a3dd1d0b941f6a8d3ab8729e19105f72d13b02a4169866263eb4c", 0.0),
    "baseline/nan_output": ("3a317c1a9c4f032a83446b2f5be784018d16cedcf28665e56ebe15d0f563d4c1", 0.0),
    "baseline/hang": ("f74148c1d72b95fcb5399759b4c914b6202710b39c5e10196d673d812b08ccd4", 0.0),
    "baseline/slow": ("63edc30039d0afe58e3287211eca374f340592b3627cde474761640f8ae2d55e", 0.0),
}
SOLUTIONS = SolutionSet(package=PACKAGE, solutions=estimator_solutions(PINS))
