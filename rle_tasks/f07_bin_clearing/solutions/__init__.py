"""Shipped solutions of 07-bin-clearing, materialised by ``rle_tasks.core.solutions``.

Each solution directory holds ``policy/`` (``__init__.py`` and helpers):

- ``reference``: depth-based detection (wrist camera at the look pose, overhead camera from the nest),
  flat tops first, Cartesian paths at a safe height, one part per trip, release only when the nest
  sensor reads empty, a blocked nest unblocked (``reference/policy``).
- ``baseline/idle``: holds its start posture, magnet off: clears nothing.
- ``baseline/floor_dropper``: the reference with its drop point over the floor: every picked part
  lands on the floor (``N_floor``), nothing is cleared.
- ``baseline/bin_slammer``: swings the magnet into the bin's far wall every 2 s (``N_bin``).
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
            sha256="58033ca964c0baf9a4a69b1763933281b1ce0318ff851e7990890f0aa98fa973",
            quick_score=0.043888888888888894,
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
            sha256="84d4d2171621cca44439ac64ea448f7fd6c07c3ed6dc367811991f3ec906ab39",
            quick_score=0.0,
            files=(
                ("policy/__init__.py", "solutions/baseline/floor_dropper.py"),
                ("policy/ref.py", f"{_REF}/__init__.py"),
                ("policy/kinematics.py", f"{_REF}/kinematics.py"),
            ),
        ),
        Solution(
            "baseline/bin_slammer",
            sha256="e4da07c7588338073d327bf46a943ea38b04aa61d0d34aee3e7b3e71127bc8fc",
            quick_score=0.0,
            files=(
                ("policy/__init__.py", "solutions/baseline/bin_slammer.py"),
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
