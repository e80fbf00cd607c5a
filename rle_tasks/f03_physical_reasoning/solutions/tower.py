"""Shipped solutions of 03-tower (see the package docstring)."""

from rle_tasks.core.solutions import Solution, SolutionSet
from rle_tasks.f03_physical_reasoning.solutions import unseal

SOLUTIONS = SolutionSet(
    package="rle_tasks.f03_physical_reasoning",
    solutions=(
        Solution(
            "reference",
            sha256="3a84378ff997e721d33cc49f4e6ddb3ca8e00b9c44f1bd22a851340bee7b34d1",
            quick_score=0.8831258833858359,
            files=((".", "solutions/reference/tower"),),
        ),
        Solution(
            "baseline/knocked_over",
            sha256="2f520035ed7cddd2e846b86e345c630f73b2090421db379b95856aee12bfb3fe",
            quick_score=0.17356657783397736,
            files=((".", "solutions/baseline/knocked_over/tower"),),
        ),
        Solution(
            "baseline/unsealed",
            sha256="a9516dcea95fd085dfa791e60c4b5842ba49f07b9475fa0ed15959822a578ee9",
            quick_score=0.0,
            base="reference",
            transforms=(unseal,),
        ),
    ),
)
