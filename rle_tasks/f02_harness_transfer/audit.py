"""Audit cases of family 02: harnesses that must fail for a named reason in quick mode (two fresh
agents): a link out of the harness, a missing manual, code that forks, opens a TCP socket, or reads
another process's environment (the sandbox refuses each)."""

from __future__ import annotations

from pathlib import Path

from rle_tasks.audit.case import Case

F02 = "02-group-01"


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


def cases() -> list[Case]:
    """Family 02's harness cases (``rle audit-verifiers``)."""
    return [
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
