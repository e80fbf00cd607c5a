"""Shipped solutions of 03-cantilever (see the package docstring)."""

from rle_tasks.core.solutions import Solution, SolutionSet
from rle_tasks.f03_physical_reasoning.solutions import unseal

SOLUTIONS = SolutionSet(
    package="rle_tasks.f03_physical_reasoning",
    solutions=(
        Solution(
            "reference",
            sha256="e44d2932c1cebb0afe5e8ae97148b876c540ee220779a8307564e280ecb856c6",
            quick_score=0.8258815160679585,
            files=((".", "solutions/reference/cantilever"),),
        ),
        Solution(
            "baseline/overreach",
            sha256="fd4079c3c0e648d05e8938cd4c5a8f4fc8490ed329a8bfae6819d3304324b4cf",
            quick_score=0.5235462280599451,
            files=((".", "solutions/baseline/overreach/cantilever"),),
        ),
        Solution(
            "baseline/unsealed",
            sha256="3d0762400de067be858912c977f9d11c9382c26ab923b0a94fbc9d252f3194c6",
            quick_score=0.0,
            base="reference",
            transforms=(unseal,),
        ),
    ),
)
