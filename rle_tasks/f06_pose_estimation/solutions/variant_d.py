"""Shipped solutions of 06-pose-d (pinned checksums and golden quick scores)."""

from rle_tasks.core.solutions import SolutionSet
from rle_tasks.f06_pose_estimation.solutions import PACKAGE, estimator_solutions

PINS = {
    "reference": ("4fcafa43d71ef85b33517c646557998328922fa6420c9bb5e85a2bb1f05473d3", 0.0),
    "baseline/wrong_shape": ("213000980b87303e879382dda7b2abc131c1a574f75983bd67cd74f580e77f5b", 0.0),
    "baseline/nan_output": ("3a317c1a9c4f032a83446b2f5be784018d16cedcf28665e56ebe15d0f563d4c1", 0.0),
    "baseline/hang": ("f74148c1d72b95fcb5399759b4c914b6202710b39c5e10196d673d812b08ccd4", 0.0),
    "baseline/slow": ("06bb6eb36af89924bbbf9525db4a188cd62f6e6106d4fe36d311f85de0381082", 0.0),
}
SOLUTIONS = SolutionSet(package=PACKAGE, solutions=estimator_solutions(PINS))
