"""Shipped solutions of 07-bin-clearing, materialised by ``rle_tasks.core.solutions``.

Each solution directory holds ``policy/`` (``__init__.py`` and helpers):

- ``reference``: depth-based detection from the wrist camera, highest part first, one part per trip,
  release only when the nest sensor reads empty (``reference/policy``).
- ``baseline/idle``: holds its start posture, magnet off: clears nothing.
- ``baseline/floor_dropper``: the reference with its drop point over the floor: every picked part
  lands on the floor (``N_floor``), nothing is cleared.
- ``baseline/short_tool``: the reference believing the stem 100 mm shorter: it slams the stem into
  the pile and the bin (``N_bin``, ``N_damage``).
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
            sha256="c03d4a756866058dbe7eb312d276bbc6a9be24dde69a08d412292d2035f952e7",
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
            "baseline/floor_dropper",
            sha256="963019b2e8441a345786f4ec04aa149c5afbf598cb17309120c057e7caffdfac" * 64,
            quick_score=0.0,
            files=(
                ("policy/__init__.py", "solutions/baseline/floor_dropper.py"),
                ("policy/ref.py", f"{_REF}/__init__.py"),
                ("policy/kinematics.py", f"{_REF}/kinematics.py"),
            ),
        ),
        Solution(
            "baseline/short_tool",
            sha256="e8d0a1ec7849c19ba035ef8a460eae7d4475a5bf4a09fa26c0b3114dc527c469" * 64,
            quick_score=0.0,
            files=(
                ("policy/__init__.py", "solutions/baseline/short_tool.py"),
                ("policy/ref.py", f"{_REF}/__init__.py"),
                ("policy/kinematics.py", f"{_REF}/kinematics.py"),
            ),
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
