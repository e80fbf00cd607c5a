"""Shipped solutions of the family's tabletop tasks (one ``SolutionSet`` per task module).

Artifacts are sealed ledgers recorded under the public development key by ``make_ledgers`` running the
agent programs of ``agents`` (which read privileged piece poses; see there):

- ``reference`` (``reference/<task>/ledger.jsonl``): cantilever: harmonic stack at 0.93 of its
  critical offsets; tower: the optimal order of ``tower.optimum`` without the wedge.
- ``baseline/overreach`` (cantilever): harmonic stack at 1.15 of its critical offsets: past its
  tipping point, the top blocks fall.
- ``baseline/knocked_over`` (tower): the reference tower, then the arm sweeps through it.
- ``baseline/unsealed`` (both): the reference ledger with its seal record cut off (score 0, reason
  ``ledger.unsealed``).
"""

from __future__ import annotations

from pathlib import Path

from rle_design.ledger.testing import cut_seal
from rle_tasks.core.solutions import Solution, SolutionSet

PACKAGE = "rle_tasks.f03_physical_reasoning"


def unseal(directory: Path) -> None:
    """Cut the seal (the last record) off ``ledger.jsonl``."""
    cut_seal(directory / "ledger.jsonl")


def unsealed(sha256: str) -> Solution:
    """``baseline/unsealed``: the reference's ledger with its seal cut off (``ledger.unsealed``, score 0)."""
    return Solution(
        "baseline/unsealed", sha256=sha256, quick_score=0.0, base="reference", transforms=(unseal,)
    )


def committed(name: str, sha256: str, quick_score: float, directory: str) -> Solution:
    """Solution ``name``: the committed directory ``directory`` (relative to the family package)."""
    return Solution(name, sha256=sha256, quick_score=quick_score, files=((".", directory),))


def solution_set(*solutions: Solution) -> SolutionSet:
    """A task's shipped solutions, reference first, overlays relative to the family package."""
    return SolutionSet(package=PACKAGE, solutions=solutions)
