"""Shipped solutions of family 01: sealed session ledgers recorded by the agent programs of ``agents``.

A submission is a session's sealed ledger (fresh nonce and opening time), so the programs are shipped
and ``make_ledgers`` records them under the public development key; the ledgers are committed gzipped
(``reference/<task id>/ledger.jsonl.gz``, ``baseline/<name>/<task id>/ledger.jsonl.gz``) and materialised by ``gunzip``.

| solution | tasks | expected score | why |
|---|---|---|---|
| ``reference`` | where a program exists for the level (see the README) | >= 0.8 x 4/5 | one pretrain episode of development, then the program on each of the five target kitchens |
| ``baseline/idle`` | all | 0 | enters the evaluation phase and never acts: five trials of zero actions |
| ``baseline/tampered`` | with a reference | 0 (``ledger.altered``) | the reference ledger with one recorded action changed after sealing |
| ``baseline/budget_exhausted`` | ``01-open-fridge-l1`` | 0 | develops until the server refuses the 50,001st step and never evaluates (d = 50,000) |
"""

from __future__ import annotations

import gzip
from pathlib import Path

from rle_tasks.core.solutions import Solution, SolutionSet

__all__ = ["LEDGER", "SOLUTIONS", "gunzip", "ledger_dir", "tamper"]

LEDGER = "ledger.jsonl"
PACKAGE = "rle_tasks.f01_robocasa_speedrun"


def gunzip(directory: Path) -> None:
    """Replace ``ledger.jsonl.gz`` by ``ledger.jsonl``."""
    gz = directory / (LEDGER + ".gz")
    (directory / LEDGER).write_bytes(gzip.decompress(gz.read_bytes()))
    gz.unlink()


def tamper(directory: Path) -> None:
    """Flip one hex digit of the last recorded action (the record's MAC no longer matches)."""
    path = directory / LEDGER
    lines = path.read_bytes().splitlines(keepends=True)
    k = max(i for i, line in enumerate(lines) if b'"kind":"steps"' in line)
    line = lines[k]
    at = line.rindex(b'"]') - 1
    digit = b"1" if line[at : at + 1] != b"1" else b"2"
    lines[k] = line[:at] + digit + line[at + 1 :]
    path.write_bytes(b"".join(lines))


def ledger_dir(task_id: str, name: str) -> str:
    """Where the ledger of solution ``name`` for ``task_id`` is committed, relative to ``solutions/``."""
    return f"{name}/{task_id}" if name == "reference" else f"baseline/{name.split('/')[-1]}/{task_id}"


def _ledger(task_id: str, name: str) -> tuple[tuple[str, str], ...]:
    return ((".", f"solutions/{ledger_dir(task_id, name)}"),)


def _set(task_id: str, pins: dict[str, tuple[str, float]]) -> SolutionSet:
    sols = []
    for name, (sha, score) in pins.items():
        if name == "baseline/tampered":
            sols.append(Solution(name, sha, score, base="reference", transforms=(tamper,)))
        else:
            sols.append(Solution(name, sha, score, files=_ledger(task_id, name), transforms=(gunzip,)))
    return SolutionSet(package=PACKAGE, solutions=tuple(sols))


PINS: dict[str, dict[str, tuple[str, float]]] = {
    "01-open-fridge-l1": {
        "baseline/idle": (
            "80c3087f936158e52c5fb08d9c40ca8b302a9eec1a395dc4671b920a34d07805",
            0.0,
        ),  # 0 of 5 trials succeeded
        "baseline/budget_exhausted": (
            "b3bf0f6d171024427aa551cee07f683c88be2bfd3997afb6cf9f664845e314b3",
            0.0,
        ),  # 0 of 5 trials succeeded (5 not played)
    },
    "01-open-fridge-l2": {
        "baseline/idle": (
            "d35d26ea4ce01bb382a8455892f35990911767afca97893c3d6db9fab4bf3b28",
            0.0,
        ),  # 0 of 5 trials succeeded
    },
    "01-open-fridge-l3": {
        "reference": (
            "7c7be83d89adc89e347d209cc3a943cf043b4766aafe0a1b883d6ca5cdfd9067",
            0.999472,
        ),  # 5 of 5 trials succeeded
        "baseline/idle": (
            "2e93279b82616f6aea2d0ae35a94bd805d0f2c9c2413877952289501fa2385ba",
            0.0,
        ),  # 0 of 5 trials succeeded
        "baseline/tampered": (
            "92310a7a98ef34f58281b380c980a3d40515a5d55c4a7bbc1861cd7d884fc22d",
            0.0,
        ),  # no verifiable session: ledger.jsonl: line 61 (seq 60) fails
    },
    "01-close-cabinet-l1": {
        "baseline/idle": (
            "f093cdb1f8555d2fe4e78f5d1b3c2764f798bdd21e2195dc899c88c583389565",
            0.0,
        ),  # 0 of 5 trials succeeded
    },
    "01-close-cabinet-l2": {
        "baseline/idle": (
            "3c0aba83e4c9b7fd28f67627e02ef0d6d8f183c2008b8fbc4b435858805091b6",
            0.0,
        ),  # 0 of 5 trials succeeded
    },
    "01-close-cabinet-l3": {
        "reference": (
            "f11bafc723abd837789a05d4a19b5e29fef959e409e20a427b2a23a0ae0af55e",
            0.9993120000000001,
        ),  # 5 of 5 trials succeeded
        "baseline/idle": (
            "9557e59f833f53761bed19bd78868a02760dfa4ade461eb987fc7563d9df25c1",
            0.0,
        ),  # 0 of 5 trials succeeded
        "baseline/tampered": (
            "b9fab6e9a5df4941ef97071fa056f25597f6dafd55f06a18913d76ba509436a8",
            0.0,
        ),  # no verifiable session: ledger.jsonl: line 73 (seq 72) fails
    },
    "01-turn-on-stove-l1": {
        "baseline/idle": (
            "992d96d5308e46488b6071962852ef9f30a9bc65c41f8df151e2c4a0c0dab7ad",
            0.0,
        ),  # 0 of 5 trials succeeded
    },
    "01-turn-on-stove-l2": {
        "reference": (
            "d5e5844004bb2e220e18f94521056e820f939627fb62f6858ac97dad16d829a3",
            0.999688,
        ),  # 5 of 5 trials succeeded
        "baseline/idle": (
            "d1642d9a1f637428db27015eef6a86169badde418a321dd5646b7842c171546a",
            0.0,
        ),  # 0 of 5 trials succeeded
        "baseline/tampered": (
            "609f6a531d8da347a16599aca30b269abb6568b5c5cbe67f6799db793e6a85f7",
            0.0,
        ),  # no verifiable session: ledger.jsonl: line 79 (seq 78) fails
    },
    "01-turn-on-stove-l3": {
        "reference": (
            "4f06f9ec35786e3f0a648657c1574d7eff375e02bbb33e4a9fa80b43d02b33ca",
            0.99968,
        ),  # 5 of 5 trials succeeded
        "baseline/idle": (
            "fd20d4931f99415afd76ee0d19bc4c10d967e4b3c6d37bf71bb92744e8443d5e",
            0.0,
        ),  # 0 of 5 trials succeeded
        "baseline/tampered": (
            "d8a46258c1bd878d1ec9c761c0a60e220d41a72001856060e583d89f0f42bc95",
            0.0,
        ),  # no verifiable session: ledger.jsonl: line 118 (seq 117) fail
    },
    "01-pnp-counter-to-drawer-l1": {
        "baseline/idle": (
            "5cf36733d904ff776de1b4aee7026bf64cd66a0a6fd50b7ef6c6f8119ccf6c4c",
            0.0,
        ),  # 0 of 5 trials succeeded
    },
    "01-pnp-counter-to-drawer-l2": {
        "baseline/idle": (
            "c5beaef9119b7018e92b3af24a97c613541ee407ba22c7feb1efabfe10e44985",
            0.0,
        ),  # 0 of 5 trials succeeded
    },
    "01-pnp-counter-to-drawer-l3": {
        "reference": (
            "cbf412cdd7c51f4d5a2df0ca1d4139e3d402f108ce4358c33a2908ea7b5ddf66",
            0.9991720000000001,
        ),  # 5 of 5 trials succeeded
        "baseline/idle": (
            "237432c2fef830704fbab7e13fb9df94914e0767ae685c43c4833ad275d86940",
            0.0,
        ),  # 0 of 5 trials succeeded
        "baseline/tampered": (
            "91509c000f87044be6fea9152ca2c4b1172f4a1b9825fb0349b573ffbb0c548a",
            0.0,
        ),  # no verifiable session: ledger.jsonl: line 87 (seq 86) fails
    },
    "01-pnp-microwave-to-counter-l1": {
        "baseline/idle": (
            "4763a34b4a52b0be5d328fd0fc920a7a0725e79cf252dcfec2364b47ce5193ad",
            0.0,
        ),  # 0 of 5 trials succeeded
    },
    "01-pnp-microwave-to-counter-l2": {
        "baseline/idle": (
            "2bd83fe76b1cdd62d8872f374344e3a46c6d336974a639fdc969409b5b970611",
            0.0,
        ),  # 0 of 5 trials succeeded
    },
    "01-pnp-microwave-to-counter-l3": {
        "reference": (
            "3d4d74c0ef5a5bd8dea3ad12f3f7af6477e8e276ce117ab2c76c1224a20bc339",
            0.9977560000000001,
        ),  # 5 of 5 trials succeeded
        "baseline/idle": (
            "cbdc7dc01abf3b5623423032ab52c15f941b01949f0218dac2348ff978b0f6f0",
            0.0,
        ),  # 0 of 5 trials succeeded
        "baseline/tampered": (
            "52736743d67dcdbe0d2d5bae133816d27bac565734d17892ea28b397144701ab",
            0.0,
        ),  # no verifiable session: ledger.jsonl: line 207 (seq 206) fail
    },
}
"""Task id -> solution name -> (pinned checksum, golden score under the public key)."""

SOLUTIONS: dict[str, SolutionSet] = {task_id: _set(task_id, pins) for task_id, pins in PINS.items()}
"""Solution sets by task id (``rle_tasks.core.solutions.declaration``)."""
