"""Shipped solutions of 07-bin-clearing, materialised by ``rle_tasks.core.solutions``.

Each solution directory holds ``policy/`` (``__init__.py`` and helpers):

- ``reference``: depth-based detection from the wrist camera, highest part first, one part per trip,
  release only when the nest sensor reads empty (``reference/policy``).
- ``baseline/idle``: holds its start posture, magnet off: clears nothing.
- ``baseline/raising``: every ``act`` raises: smoke failure, reward capped at 0.1 (and 0 cleared).
- ``baseline/hanging``: ``act`` never returns: the hang cap ends it; smoke failure, cap 0.1.

Golden scores: quick mode (one hidden pile), public development key.
"""

from __future__ import annotations

from rle_tasks.core.solutions import Solution, SolutionSet

_REF = "solutions/reference/policy"

SOLUTIONS = SolutionSet(
    package="rle_tasks.f07_bin_clearing",
    solutions=(
        Solution(
            "reference",
            sha256="792f8c7f1bd2bb53ba1b14d1220c698bb5304d7640982656974e367384a37099",
            quick_score=0.0,
            files=(
                ("policy/__init__.py", f"{_REF}/__init__.py"),
                ("policy/kinematics.py", f"{_REF}/kinematics.py"),
            ),
        ),
        Solution(
            "baseline/idle",
            sha256="7a82fb955b80b45f66498b79b32dd5942d9b68451da5c0abd758415f929ac559",
            quick_score=0.0,
            files=(("policy/__init__.py", "solutions/baseline/idle.py"),),
        ),
        Solution(
            "baseline/raising",
            sha256="a3e4cc0815671c4d1e5becdf181701ffeceb1a163b781afd91f4214b232b2f12",
            quick_score=0.0,
            files=(("policy/__init__.py", "solutions/baseline/raising.py"),),
        ),
        Solution(
            "baseline/hanging",
            sha256="4ce55a21129fb324798a05fafdd3ece2fb0b96a12390b124050e3cd18e3452b1",
            quick_score=0.0,
            files=(("policy/__init__.py", "solutions/baseline/hanging.py"),),
        ),
    ),
)
