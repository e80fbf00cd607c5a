"""Audit cases of family 08 for the workshop rules (issue 45): the reference with one part sunk into
another part welded to it, refused by name (validity fails: the score is capped at 0.15)."""

from __future__ import annotations

import shutil
from pathlib import Path

from lxml import etree

from rle_tasks.audit.case import Case
from rle_tasks.core.solutions import materialise
from rle_tasks.f08_mobile_base.scoring import CAP

TASK = "08-mobile-base"


def _battery_into_the_frame(d: Path) -> Path:
    """The reference battery moved 20 mm forward, into the cross member it is bolted to."""
    shutil.copytree(materialise(TASK, "reference"), d, dirs_exist_ok=True, symlinks=True)
    path = d / "robot.xml"
    tree = etree.parse(str(path))
    battery = next(b for b in tree.getroot().iter("body") if b.get("name") == "battery")
    x, y, z = (float(v) for v in battery.get("pos").split())
    battery.set("pos", f"{x + 0.02:.4f} {y:.4f} {z:.4f}")
    tree.write(str(path))
    return d


def cases() -> list[Case]:
    return [
        Case(
            "physics/f08_battery_in_the_frame",
            TASK,
            "f08.interpenetration",
            _battery_into_the_frame,
            max_score=CAP,
        )
    ]
