"""Shipped solutions of family 02: ``agent_harness/`` directories, committed as files.

| solution | groups | expected | why |
|---|---|---|---|
| ``reference`` | those with a reference harness (README) | >= 0.6 | the scripted fresh agent calls the harness's entry point, which perceives through the segmenter and depth and solves the held-out task |
| ``baseline/empty`` | all | 0 | a manual without an entry point: the fresh agent cannot act |
| ``baseline/missing_function`` | all | 0 | the manual names ``agent_harness.skills:solve``, which does not exist |
| ``baseline/reads_hidden_state`` | all | 0 | the entry point reads the verifier's files outside its directory; the sandbox refuses (``sandbox.violation``) |
"""

from __future__ import annotations

from pathlib import Path

from rle_tasks.core.solutions import Solution, SolutionSet

__all__ = ["PINS", "SOLUTIONS", "add_harness_modules"]

PACKAGE = "rle_tasks.f02_harness_transfer"
BASELINES = ("empty", "missing_function", "reads_hidden_state")


SHARED_MODULES = ("robot.py", "geometry.py", "motion.py")
"""Kitchen harness modules the reference harness uses (generated into it, not stored twice)."""
TUNED_CONSTANTS = {"motion.py": {"CORRECT_GAIN": "0.25", "CORRECT_MAX": "0.08", "CORRECT_MAX_ROT": "0.0"}}
"""Module -> top-level constant -> the reference's value. The reference integrates the position error
near a goal at half the kitchen harness's gain with twice its bound, and does not correct the
orientation (a zero bound keeps the orientation bias at zero, so the target is the goal itself)."""


def tune_constants(text: str, values: dict[str, str]) -> str:
    """``text`` with each top-level ``NAME = ...`` line of ``values`` set to its value.

    Raises:
        ValueError: A name is not assigned on exactly one top-level line (the kitchen harness changed).
    """
    lines = text.splitlines(keepends=True)
    for name, value in values.items():
        hits = [i for i, line in enumerate(lines) if line.startswith(f"{name} = ")]
        if len(hits) != 1:
            raise ValueError(f"{name} is assigned on {len(hits)} top-level lines, not one")
        lines[hits[0]] = f"{name} = {value}\n"
    return "".join(lines)


def add_harness_modules(directory: Path) -> None:
    """Copy the kitchen harness's ``SHARED_MODULES`` into ``agent_harness/`` with the reference's
    ``TUNED_CONSTANTS`` (the harness must be self-contained: a fresh agent has nothing else)."""
    from rle_tasks.envs.kitchen.workspace import HARNESS

    for name in SHARED_MODULES:
        text = (HARNESS / name).read_text().replace("from harness.", "from agent_harness.")
        text = tune_constants(text, TUNED_CONSTANTS.get(name, {}))
        (directory / "agent_harness" / name).write_text(text)


def _set(task_id: str, pins: dict[str, tuple[str, float]], reference: str | None) -> SolutionSet:
    sols = []
    for name, (sha, score) in pins.items():
        if name == "reference":
            files = ((".", f"solutions/reference/{reference}"),)
            sols.append(Solution(name, sha, score, files=files, transforms=(add_harness_modules,)))
        else:
            sols.append(
                Solution(name, sha, score, files=((".", f"solutions/baseline/{name.split('/')[1]}"),))
            )
    return SolutionSet(package=PACKAGE, solutions=tuple(sols))


REFERENCES: dict[str, str] = {
    g: "kitchen"
    for g in (
        "02-group-01",
        "02-group-02",
        "02-group-03",
        "02-group-06",
        "02-group-09",
        "02-group-10",
        "02-group-12",
    )
}
"""Task id -> reference harness folder under ``solutions/reference``."""
BASELINE_PINS: dict[str, tuple[str, float]] = {
    "baseline/empty": ("9a7e1683a0d2c269f53ecf8f24f2aa74eb4ef0f8778a8ed68c0c8485eb2f91ae", 0.0),
    "baseline/missing_function": ("93b11184b203d1c36e5b9d2b1bd7d627ba14cd0cdb30213e125551bb306869f8", 0.0),
    "baseline/reads_hidden_state": ("a7482a8c079e624311771c1064ce6af9691d68cdb0fbf1baa54d8bc0ac111516", 0.0),
}
"""The baselines are the same files for every group (checksum, golden quick score)."""
REFERENCE_PINS: dict[str, tuple[str, float]] = {
    # quick mode runs two of the five agents and scores their mean (partial): two successes -> 1.0; group 6:
    # agent 0 succeeds, agent 1 reaches 3 of 4 conjuncts (b = 1: s_trial 2/3) -> 0.8333 (README, "Solutions")
    "02-group-01": ("189622f679b7a3151326f6e7afe30096b07fbdf3f0bc9725a879373fd0fcb0e7", 1.0),
    "02-group-02": ("189622f679b7a3151326f6e7afe30096b07fbdf3f0bc9725a879373fd0fcb0e7", 1.0),
    "02-group-03": ("189622f679b7a3151326f6e7afe30096b07fbdf3f0bc9725a879373fd0fcb0e7", 1.0),
    "02-group-06": ("189622f679b7a3151326f6e7afe30096b07fbdf3f0bc9725a879373fd0fcb0e7", 0.833333333333),
    "02-group-09": ("189622f679b7a3151326f6e7afe30096b07fbdf3f0bc9725a879373fd0fcb0e7", 1.0),
    "02-group-10": ("189622f679b7a3151326f6e7afe30096b07fbdf3f0bc9725a879373fd0fcb0e7", 1.0),
    "02-group-12": ("189622f679b7a3151326f6e7afe30096b07fbdf3f0bc9725a879373fd0fcb0e7", 1.0),
}
"""Task id -> the reference's (checksum, golden quick score under the public key)."""
BASELINE_GROUPS = tuple(REFERENCE_PINS)
"""Groups that ship the baselines: every group with a reference, so each one's verifier is shown an
artifact that must fail beside the one that must pass."""
PINS: dict[str, dict[str, tuple[str, float]]] = {
    tid: ({"reference": REFERENCE_PINS[tid]} if tid in REFERENCE_PINS else {})
    | (BASELINE_PINS if tid in BASELINE_GROUPS else {})
    for tid in sorted(set(BASELINE_GROUPS) | set(REFERENCE_PINS))
}
"""Task id -> solution name -> (pinned checksum, golden quick score under the public key)."""

SOLUTIONS: dict[str, SolutionSet] = {tid: _set(tid, pins, REFERENCES.get(tid)) for tid, pins in PINS.items()}
"""Solution sets by task id."""
