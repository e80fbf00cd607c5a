"""Audit cases of family 08, each the reference altered in one place: hostile MJCF and meshes
(``xml_cases``), physics cheats refused by the contract, hostile controller code (``code_cases``),
generated additions under every stock body, and the workshop rules (issue 45: a part sunk into another
part welded to it).

Bounds: the design scores zero for anything that fails loading and is capped at 0.15 (``CAP``) for a
failed validity checkpoint; faults of the submitted controller lose shelf integration (<= 0.85).
"""

from __future__ import annotations

import re
import shutil
from pathlib import Path

from lxml import etree

from rle_tasks.audit.artifacts import Target, edit_xml, first_body_attr, inject_root, weld
from rle_tasks.audit.case import Case
from rle_tasks.audit.code_cases import code_cases
from rle_tasks.audit.generated import Addition, generated_cases
from rle_tasks.audit.xml_cases import xml_cases
from rle_tasks.core.solutions import materialise
from rle_tasks.f08_mobile_base.scoring import CAP

TASK = "08-mobile-base"
TARGET = Target(TASK, xml="robot.xml", code_file="controller.py")
CODE_CAP = 0.85
BODIES = ("chassis", "wheel_fl", "wheel_fr", "wheel_rl", "wheel_rr", "battery", "universal_adapter")
"""Stock bodies the generated additions go under."""

PHYSICS = [
    ("gravcomp", "contract.gravcomp", first_body_attr('gravcomp="1"')),
    ("gravity_changed", "contract.option_changed", inject_root('<option gravity="0 0 -5"/>')),
    ("weld_to_world", "contract.world_weld", weld("weld")),
    (
        "battery_in_mid_air",
        "f08.floating_part",
        lambda xml: re.sub(r'(<body name="battery" pos="[^ ]+ [^ ]+ )([^"]+)"', r'\g<1>0.2"', xml, count=1),
    ),
    (
        "inertial_below_floor",
        "f08.inertial_mismatch",
        # the reference chassis' own mass, declared 0.5 m below its frame (under the floor)
        lambda xml: re.sub(
            r'(<body name="chassis"[^>]*>)',
            r'\1<inertial pos="0 0 -0.5" mass="6.8904" diaginertia="0.5 0.5 0.5"/>',
            xml,
            count=1,
        ),
    ),
]

"""Physics cheats: (name, expected code, edit of robot.xml)."""


def expected(a: Addition) -> tuple[str, ...]:
    """Codes a generated addition must produce (the first is the corpus case's code)."""
    if a.kind == "geom":
        return ("catalog.non_catalog_mass",) if a.body == "chassis" else ("f08.part_modified",)
    if a.kind == "body":
        return ("f08.extra_body",)
    return ("f08.extra_joints", "f08.extra_body")


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
    """Family 08's cases (``rle audit-verifiers``)."""
    out = xml_cases(TARGET, 0.0)
    out += [
        Case("artifact/f08_missing_dir", TASK, "artifact.missing_dir", lambda d: d / "does-not-exist"),
        Case("artifact/f08_empty_dir", TASK, "artifact.missing_file", lambda d: d),
    ]
    out += [
        Case(f"physics/f08_{n}", TASK, code, edit_xml(TARGET, edit), max_score=CAP)
        for n, code, edit in PHYSICS
    ]
    out += code_cases(TARGET, "control", "a[3]", CODE_CAP)
    out += generated_cases(TARGET, BODIES, expected, CAP, compile_cap=0.0)
    out.append(
        Case(
            "physics/f08_battery_in_the_frame",
            TASK,
            "f08.interpenetration",
            _battery_into_the_frame,
            max_score=CAP,
        )
    )
    return out
