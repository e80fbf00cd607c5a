"""Shipped solutions of family 02: ``agent_harness/`` directories, committed as files.

| solution | groups | expected | why |
|---|---|---|---|
| ``reference`` | those with a reference harness (README) | >= 0.6 | the scripted fresh agent calls the harness's entry point, which perceives through the segmenter and depth and solves the held-out task |
| ``baseline/empty`` | all | 0 | a manual without an entry point: the fresh agent cannot act |
| ``baseline/missing_function`` | all | 0 | the manual names ``agent_harness.skills:solve``, which does not exist |
| ``baseline/reads_hidden_state`` | all | 0 | the entry point reads the verifier's files outside its directory; the sandbox refuses (``sandbox.violation``) |
"""

from __future__ import annotations

from rle_tasks.core.solutions import Solution, SolutionSet

__all__ = ["PINS", "SOLUTIONS"]

PACKAGE = "rle_tasks.f02_harness_transfer"
BASELINES = ("empty", "missing_function", "reads_hidden_state")


def _set(task_id: str, pins: dict[str, tuple[str, float]], reference: str | None) -> SolutionSet:
    sols = []
    for name, (sha, score) in pins.items():
        src = (
            f"solutions/reference/{reference}"
            if name == "reference"
            else f"solutions/baseline/{name.split('/')[1]}"
        )
        sols.append(Solution(name, sha, score, files=((".", src),)))
    return SolutionSet(package=PACKAGE, solutions=tuple(sols))


REFERENCES: dict[str, str] = {}
"""Task id -> reference harness folder under ``solutions/reference``."""
PINS: dict[str, dict[str, tuple[str, float]]] = {}
"""Task id -> solution name -> (pinned checksum, golden quick score under the public key)."""

SOLUTIONS: dict[str, SolutionSet] = {tid: _set(tid, pins, REFERENCES.get(tid)) for tid, pins in PINS.items()}
"""Solution sets by task id."""
