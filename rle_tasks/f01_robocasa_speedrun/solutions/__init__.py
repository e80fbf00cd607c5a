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

from rle_design.ledger.testing import flip_last_action
from rle_tasks.core.solutions import Solution, SolutionSet

__all__ = ["LEDGER", "SOLUTIONS", "gunzip", "harbor_oracle", "ledger_dir", "tamper"]

LEDGER = "ledger.jsonl"
PACKAGE = "rle_tasks.f01_robocasa_speedrun"


def gunzip(directory: Path) -> None:
    """Replace ``ledger.jsonl.gz`` by ``ledger.jsonl``."""
    gz = directory / (LEDGER + ".gz")
    (directory / LEDGER).write_bytes(gzip.decompress(gz.read_bytes()))
    gz.unlink()


def tamper(directory: Path) -> None:
    """Flip one hex digit of the last recorded action (the record's MAC no longer matches)."""
    flip_last_action(directory / LEDGER)


def harbor_oracle(spec, dest: Path) -> str | None:
    """The Harbor oracle that plays the task through the development sidecar (``oracle``)."""
    from .oracle import harbor_oracle as write

    return write(spec, dest)


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
        "reference": (
            "a80dfe89ab004644ce734fb70d24c56a26c12cb450b147191d6df82ec5d5dd62",
            0.9978560000000001,
        ),  # 5 of 5 trials succeeded
        "baseline/idle": (
            "5b399425c6ecf316b7bb037341677c5806c95185fceb831107324b76953ce21c",
            0.0,
        ),  # 0 of 5 trials succeeded
        "baseline/budget_exhausted": (
            "1ac76778a40de0d13c4432547e09d7eff8b27ff09066a2d46a3a4ad6ec7736e8",
            0.0,
        ),  # 0 of 5 trials succeeded (5 not played)
        "baseline/tampered": (
            "3462f488cfb4d89780e22358c4e4f3bce3c0cba70a9210b3b30e98caf3e5c985",
            0.0,
        ),  # no verifiable session: ledger.jsonl: line 106 (seq 105) fails its MAC
    },
    "01-open-fridge-l2": {
        "reference": (
            "18a9b1b228f31e41ddc4a72a0be6e39873ba946a34498ac09c392c4336da0dad",
            0.999464,
        ),  # 5 of 5 trials succeeded
        "baseline/idle": (
            "a0238472ccaa0e11b77463185c2ca7f807d65667a076b1edef68fbd0571787e7",
            0.0,
        ),  # 0 of 5 trials succeeded
        "baseline/tampered": (
            "817d50c8b363f61252bbe50f0592aa23108d0b235a2470d43c72438c15874c52",
            0.0,
        ),  # no verifiable session: ledger.jsonl: line 61 (seq 60) fails
    },
    "01-open-fridge-l3": {
        "reference": (
            "1194dfaa49328e88afbfd17b96e7d91ec973186039a696325c7fe64f54e513d2",
            0.999472,
        ),  # 5 of 5 trials succeeded
        "baseline/idle": (
            "d46a11b658551a0c7d5949d01a951f154eae0fdd368c5df8a2ad2aa070b00595",
            0.0,
        ),  # 0 of 5 trials succeeded
        "baseline/tampered": (
            "93e5a898f6932940da924b7c138d5087b7a741bc70049812d002982a157b4c27",
            0.0,
        ),  # no verifiable session: ledger.jsonl: line 61 (seq 60) fails
    },
    "01-close-cabinet-l1": {
        "reference": (
            "d8bcf38c00e6acd47f989e08316f2dc062730ee0c88c2185bdf0ef38353c995e",
            0.9979960000000001,
        ),  # 5 of 5 trials succeeded
        "baseline/idle": (
            "42ca0a9b7ca149506c14aabdffe717a89fe9fce7ede9dfaf63e0267e4d232a60",
            0.0,
        ),  # 0 of 5 trials succeeded
        "baseline/tampered": (
            "80410ef6ca28bf011ec2ed99f1eae3124a0a0fdc27d559ee8f5601899cc8a3a9",
            0.0,
        ),  # no verifiable session: ledger.jsonl: line 97 (seq 96) fails its MAC
    },
    "01-close-cabinet-l2": {
        "reference": (
            "c910c88ae69915a73e02acbc2e1ee99eabac2f5e9bb60f15870424fef27f4faf",
            0.9993120000000001,
        ),  # 5 of 5 trials succeeded
        "baseline/idle": (
            "5d18bf10a5f3aed78577df748e97844a3fbb5b855141e481ee7e90ab0622ea95",
            0.0,
        ),  # 0 of 5 trials succeeded
        "baseline/tampered": (
            "14c35b38aa36068e460b6da35e35d37efbbeba80a6dc93d3d70ac99fa905caaa",
            0.0,
        ),  # no verifiable session: ledger.jsonl: line 73 (seq 72) fails
    },
    "01-close-cabinet-l3": {
        "reference": (
            "4b0a44823b04607761822f4c64da5999e571465cccfaa79872e9c581342f550f",
            0.9993120000000001,
        ),  # 5 of 5 trials succeeded
        "baseline/idle": (
            "b3acfe7445ef3015d47508759e5c5278285c0ab5eb7694d2cf3a14a2b846f86a",
            0.0,
        ),  # 0 of 5 trials succeeded
        "baseline/tampered": (
            "cd32c0bb73f033a264f234300e1d475a0047112052a518a3e2a225cf322e635a",
            0.0,
        ),  # no verifiable session: ledger.jsonl: line 73 (seq 72) fails
    },
    "01-turn-on-stove-l1": {
        "reference": (
            "c6ccc8a8e3109802efa51d57e7b5fa74c480702119adb9ad558ef0732fa589d1",
            0.9982080000000001,
        ),  # 5 of 5 trials succeeded
        "baseline/idle": (
            "3361ddb6c2f6db0e231f9e5390b559adbb65d8db898c0a20427ca13f925c08e9",
            0.0,
        ),  # 0 of 5 trials succeeded
        "baseline/tampered": (
            "94d2b2c020c22d973d75fa84603a69a73804dbd1b9a1069a5c3a9daf11fea6b3",
            0.0,
        ),  # no verifiable session: ledger.jsonl: line 134 (seq 133) fails its MAC
    },
    "01-turn-on-stove-l2": {
        "reference": (
            "1d78439adefb0102f4048668373e60de12e0786ac01523136695033187e09d25",
            0.999688,
        ),  # 5 of 5 trials succeeded
        "baseline/idle": (
            "1e1655fba971d5d80f1dc7bf8db38f291235dd60a31fc8db4f15f9da813ae92a",
            0.0,
        ),  # 0 of 5 trials succeeded
        "baseline/tampered": (
            "ac04bf40f3b9ff82588d2b039834636fefe8b26b475afa422524ca2e637ed7cc",
            0.0,
        ),  # no verifiable session: ledger.jsonl: line 79 (seq 78) fails
    },
    "01-turn-on-stove-l3": {
        "reference": (
            "7d41e41f9dd094ad7c23debb1f05fee0d41b0260de039c2b80e213e835599ab1",
            0.99968,
        ),  # 5 of 5 trials succeeded
        "baseline/idle": (
            "183fc65f70a10907e9470bdd69f9c6b9b0b66b92bae619018b614637903047c1",
            0.0,
        ),  # 0 of 5 trials succeeded
        "baseline/tampered": (
            "b3b21545098d1b3cbd8545bc58036911f6d5e3c35eee91ceed5cf09ce8d04d6f",
            0.0,
        ),  # no verifiable session: ledger.jsonl: line 118 (seq 117) fail
    },
    "01-pnp-counter-to-drawer-l1": {
        "baseline/idle": (
            "3a4f1c471e6d84f08f3653a57eaa74a5e908a2a07c5d466bbec3867eef130978",
            0.0,
        ),  # 0 of 5 trials succeeded
    },
    "01-pnp-counter-to-drawer-l2": {
        "reference": (
            "e289a4a6ff0659132df353304b98eade70cfe89de716a67890e7811ae15efb7f",
            0.9991920000000001,
        ),  # 5 of 5 trials succeeded
        "baseline/idle": (
            "4ec3d821d3acad1f8f22df709b6dbd90507f2f16118c2eac4707decb31b13e20",
            0.0,
        ),  # 0 of 5 trials succeeded
        "baseline/tampered": (
            "e8b95d4033e84b00f0b0384965eace1f2509262f6e428c7c043b2e601e4564a0",
            0.0,
        ),  # no verifiable session: ledger.jsonl: line 91 (seq 90) fails
    },
    "01-pnp-counter-to-drawer-l3": {
        "reference": (
            "839245e1397c3b1aa0b13ed6e7f7a8db4043efd66698789eb398bdcb46626631",
            0.9991720000000001,
        ),  # 5 of 5 trials succeeded
        "baseline/idle": (
            "c74cc83b02717f087426ab6bec8e6c737d487b9b4304133a7a590ce962239c4a",
            0.0,
        ),  # 0 of 5 trials succeeded
        "baseline/tampered": (
            "90a667c05fe77f61243fff7b20d11726c43ee4f4229d3dea9384fcac7cf0cfe7",
            0.0,
        ),  # no verifiable session: ledger.jsonl: line 87 (seq 86) fails
    },
    "01-pnp-microwave-to-counter-l1": {
        "baseline/idle": (
            "270df0e6176786047fb5874bafad2e137f1050aa42737ce36269975e258297d3",
            0.0,
        ),  # 0 of 5 trials succeeded
    },
    "01-pnp-microwave-to-counter-l2": {
        "reference": (
            "59f715e29f51cf8ec0d719a40651f28e2ed2b5e8d40e5c17027a241fe0b5bb22",
            0.7979200000000002,
        ),  # 4 of 5 trials succeeded
        "baseline/idle": (
            "9acc3b2c9f1f5d8b344882fa85f6dafe5306620c9683c45ed69f09b50a1e1324",
            0.0,
        ),  # 0 of 5 trials succeeded
        "baseline/tampered": (
            "b9049be44c35239d0e07e40bc1178743c2177e57200f9fef4f8d9550a9330dd0",
            0.0,
        ),  # no verifiable session: ledger.jsonl: line 234 (seq 233) fails
    },
    "01-pnp-microwave-to-counter-l3": {
        "reference": (
            "d2d714f8759af9e04aa13559979c2c872bb5793689fe8c89b0c774846907e3dd",
            0.9977560000000001,
        ),  # 5 of 5 trials succeeded
        "baseline/idle": (
            "26d784c5468abb4876af41828918fedc7a9beb82c2cd6fe75129b3e2496bb31d",
            0.0,
        ),  # 0 of 5 trials succeeded
        "baseline/tampered": (
            "757d2d937808fd18024b8614f9449321edb4de99998decaaf071e75c37be9539",
            0.0,
        ),  # no verifiable session: ledger.jsonl: line 207 (seq 206) fail
    },
}
"""Task id -> solution name -> (pinned checksum, golden score under the public key)."""

SOLUTIONS: dict[str, SolutionSet] = {task_id: _set(task_id, pins) for task_id, pins in PINS.items()}
"""Solution sets by task id (``rle_tasks.core.solutions.declaration``)."""
