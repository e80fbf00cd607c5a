"""Adversarial artifacts of the kitchen families: ledgers for family 01, harnesses for family 02.

Family 01 verifies a sealed session ledger under the audit's private secret: a rehearsal ledger signed
with the public development key, one signed for another task, one of a session served with another
budget, and a missing or linked ledger all score 0 with their code. Family 02 runs (quick mode, two
fresh agents) harnesses that must fail for a named reason: a link out of the harness, a missing manual,
code that forks, opens a TCP socket, or reads another process's environment (the sandbox refuses each).
"""

from __future__ import annotations

import shutil
from pathlib import Path

from rle_design.ledger.records import LedgerWriter
from rle_tasks.audit.case import Case
from rle_tasks.core.solutions import materialise

F01, F02 = "01-turn-on-stove-l3", "02-group-01"


def _public_reference(d: Path) -> Path:
    """The shipped reference ledger, recorded under the public key: no use under a private secret."""
    shutil.copyfile(materialise(F01, "reference") / "ledger.jsonl", d / "ledger.jsonl")
    return d


def _linked(d: Path) -> Path:
    (d / "ledger.jsonl").symlink_to(materialise(F01, "reference") / "ledger.jsonl")
    return d


def _signed(task_id: str, budget: int):
    """A sealed ledger written with the audit secret's key of ``task_id``, opened as a session of
    ``budget`` development steps, with one reset."""

    def build(d: Path) -> Path:
        from rle_tasks.audit.case import AUDIT_SECRET
        from rle_tasks.core.devenv import ledger_key
        from rle_tasks.f01_robocasa_speedrun.task import BUDGET, KITCHEN_TASKS, scenes

        kitchen = next(k for k in KITCHEN_TASKS if k.task == "TurnOnStove")
        meta = {
            "scene_set": scenes(kitchen, 3, AUDIT_SECRET, image_size=None).fingerprint(),
            "evaluation": {"trials": 5, "actions_per_trial": 1000, "wall_time_s": 3600.0},
            "budget": budget,
            "wall_time_s": BUDGET.wall_time_s,
        }
        w = LedgerWriter(d / "ledger.jsonl", ledger_key(AUDIT_SECRET, task_id), task_id, meta)
        w.append("reset", {"steps": 1, "time": 0.0, "scene": "pretrain/0/0", "phase": "development"})
        w.seal(1)
        return d

    return build


def _harness(files: dict[str, str], manual: str | None = "Entry point: `agent_harness.entry:solve`\n"):
    def build(d: Path) -> Path:
        h = d / "agent_harness"
        h.mkdir()
        if manual is not None:
            (h / "MANUAL.md").write_text(manual)
        for name, text in files.items():
            (h / name).write_text(text)
        return d

    return build


def _linked_harness(d: Path) -> Path:
    _harness({"entry.py": "def solve(client, instruction):\n    client.reset()\n"})(d)
    (d / "agent_harness" / "notes.md").symlink_to("/etc/hostname")
    return d


_FORK = "import os\n\ndef solve(client, instruction):\n    client.reset()\n    os.fork()\n"
_TCP = (
    "import socket\n\ndef solve(client, instruction):\n    client.reset()\n"
    "    socket.create_connection(('127.0.0.1', 80), timeout=1)\n"
)
_ENVIRON = "import os\n\ndef solve(client, instruction):\n    client.reset()\n    return open(f'/proc/{os.getppid()}/environ').read()\n"


def kitchen_cases() -> list[Case]:
    """Family 01 ledger cases and family 02 harness cases."""
    return [
        Case(
            "ledger/f01_public_rehearsal_ledger", F01, "ledger.forged_key", _public_reference, wall_cap_s=30.0
        ),
        Case("ledger/f01_linked_ledger", F01, "ledger.missing", _linked, wall_cap_s=30.0),
        Case("ledger/f01_missing_ledger", F01, "ledger.missing", lambda d: d, wall_cap_s=30.0),
        Case(
            "ledger/f01_other_task_key",
            F01,
            "ledger.forged_key",
            _signed("01-turn-on-stove-l2", 50_000),
            wall_cap_s=30.0,
        ),
        Case(
            "ledger/f01_other_budget", F01, "ledger.wrong_limits", _signed(F01, 10_000_000), wall_cap_s=30.0
        ),
        Case("harness/f02_no_manual", F02, "f02.no_manual", _harness({}, manual=None), wall_cap_s=30.0),
        Case("harness/f02_link_out", F02, "f02.harness_unusable", _linked_harness, wall_cap_s=60.0),
        Case(
            "harness/f02_fork", F02, "f02.sandbox.forbidden", _harness({"entry.py": _FORK}), wall_cap_s=90.0
        ),
        Case("harness/f02_tcp", F02, "f02.sandbox.forbidden", _harness({"entry.py": _TCP}), wall_cap_s=90.0),
        Case(
            "harness/f02_parent_environ",
            F02,
            "f02.sandbox.forbidden",
            _harness({"entry.py": _ENVIRON}),
            wall_cap_s=90.0,
        ),
    ]
