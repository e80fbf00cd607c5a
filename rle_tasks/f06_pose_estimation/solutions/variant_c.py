"""Shipped solutions of 06-pose-c-learned (pinned checksums and golden quick scores)."""

from rle_tasks.core.solutions import Solution, SolutionSet
from rle_tasks.f06_pose_estimation.solutions import PACKAGE

SOLUTIONS = SolutionSet(
    package=PACKAGE,
    solutions=(
        Solution(
            "baseline/nan_output",
            "fb14917ff26fe0d21ca7f0789794ddd1909639fbde4dd9b35de53572710066f8",
            0.0,
            files=(("model.pt", "solutions/baseline/nan_model/model.pt"),),
        ),
        Solution(
            "baseline/big_model",
            "e6cbb0b7637563c34c699f892cc0794b2b8c26bb382bf9df166a343c2be7d04d",
            0.0,
            files=(("model.pt", "solutions/baseline/big_model/model.pt"),),
        ),
    ),
)
