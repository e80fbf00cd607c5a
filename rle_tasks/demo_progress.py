"""Progress of ``rle demo``: the time left per family and in all, estimated from the seconds each
artifact took on the 2-core reference machine and scaled by how this machine has compared so far."""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

from rle_tasks.core.task import TaskSpec

DEMO_TIMES = Path(__file__).with_name("demo_times.json")
"""Seconds each artifact of ``rle demo`` took on the 2-core reference machine (``times.json`` of a
demo run copied here), for the progress bar's estimates; keys ``quick|full:task:solution``."""


class Estimate:
    """Time left per family and in total, from ``DEMO_TIMES`` scaled by how this machine has compared
    with them so far (an artifact not listed counts the listed mean)."""

    def __init__(self, runs: Sequence[tuple[TaskSpec, str]], full: bool) -> None:
        try:
            known = json.loads(DEMO_TIMES.read_text())
        except (OSError, ValueError):
            known = {}
        self.mode = "full" if full else "quick"
        mean = sum(known.values()) / len(known) if known else 30.0
        self.expected = {(t.id, n): float(known.get(f"{self.mode}:{t.id}:{n}", mean)) for t, n in runs}
        self.family = {(t.id, n): t.family for t, n in runs}
        self.spent: dict[str, float] = {}
        self.scale_num = self.scale_den = 0.0

    def done(self, task: TaskSpec, name: str, seconds: float) -> None:
        self.spent[f"{self.mode}:{task.id}:{name}"] = round(seconds, 1)
        self.scale_num += seconds
        self.scale_den += self.expected.pop((task.id, name), seconds)

    def left(self, family: int) -> str:
        scale = self.scale_num / self.scale_den if self.scale_den > 0 else 1.0
        fam = scale * sum(v for k, v in self.expected.items() if self.family[k] == family)
        total = scale * sum(self.expected.values())
        return f"F{family:02d} ~{fam / 60:.1f} min left, all ~{total / 60:.1f} min"

    def write(self, path: Path) -> None:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(self.spent, indent=1) + "\n")
