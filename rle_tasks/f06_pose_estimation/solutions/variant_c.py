"""Shipped solutions of 06-pose-c-learned (pinned checksums and golden quick scores)."""

from rle_tasks.core.solutions import Solution, SolutionSet
from rle_tasks.f06_pose_estimation.solutions import PACKAGE

SOLUTIONS = SolutionSet(
    package=PACKAGE,
    solutions=(
        Solution("baseline/nan_output", "0" * 64, 0.0, files=(("model.pt", "solutions/baseline/nan_model/model.pt"),)),
        Solution("baseline/big_model", "0" * 64, 0.0, files=(("model.pt", "solutions/baseline/big_model/model.pt"),)),
    ),
)
