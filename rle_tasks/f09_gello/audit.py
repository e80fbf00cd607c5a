"""Audit cases of family 09 for the workshop rules (issue 45): each the reference with one unbuildable
change on every leader, refused by name (every checkpoint of a refused leader scores 0), or scored
down pose by pose with the cause named (a part inside the next link across a joint)."""

from __future__ import annotations

import shutil
from collections.abc import Callable
from pathlib import Path

import numpy as np
from lxml import etree

from rle_tasks.audit.runner import Case
from rle_tasks.core.solutions import materialise

TASK = "09-gello"
ROBOTS = ("panda", "ur5e", "xarm7")
REFUSED = 0.0
"""A leader refused on every robot scores 0 (issue 45: the adapted reference arm's checkpoints too)."""
SCORED_DOWN = 0.9
"""Bound for a case scored pose by pose: below a perfect score (the routed reference itself scores
0.84 quick, with part of its motion-clearance credit)."""


def _body(root, name: str):
    return next(b for b in root.iter("body") if b.get("name") == name)


def _geom(root, name: str):
    return next(g for g in root.iter("geom") if g.get("name") == name)


def _edit(edit: Callable[[etree._Element], None]) -> Callable[[Path], Path]:
    def build(d: Path) -> Path:
        shutil.copytree(materialise(TASK, "reference"), d, dirs_exist_ok=True, symlinks=True)
        for robot in ROBOTS:
            path = d / robot / "lead.xml"
            tree = etree.parse(str(path))
            edit(tree.getroot())
            tree.write(str(path))
        return d

    return build


def _displaced_inertial(root) -> None:
    """counterweight1's steel and rod, its inertial declared 0.2 m away from them."""
    cw = _body(root, "counterweight1")
    cw.insert(0, etree.Element("inertial", pos="0.2 0 0", mass="0.18", diaginertia="1e-5 1e-5 1e-5"))


def _dense_steel(root) -> None:
    """counterweight1's sphere 1 % above the catalog's heaviest steel (7870 kg/m^3)."""
    g = _geom(root, "counterweight1_steel")
    g.set("mass", f"{7870 * 1.01 * 4 / 3 * np.pi * float(g.get('size')) ** 3:.9g}")


def thin_strut(root) -> None:
    """A 0.4 mm x 3 mm x 12 cm PLA strut seated in link3's servo housing, 0.18 kg of steel at its end."""
    strut = etree.SubElement(_body(root, "link3"), "body", name="strut")
    etree.SubElement(
        strut,
        "geom",
        name="strut_pla",
        type="box",
        size="0.06 0.0015 0.0002",
        pos="0.065 0 0",
        density="1240",
    )
    side = (0.18 / 7850) ** (1 / 3) / 2
    etree.SubElement(
        strut,
        "geom",
        name="strut_steel",
        type="box",
        size=f"{side:.6f} {side:.6f} {side:.6f}",
        pos=f"{0.125 + side:.6f} 0 0",
        mass="0.18",
    )


def _sunk_into_next_link(root) -> None:
    """A printed block on link3's servo housing reaching 70 mm along where link2's tube runs."""
    block = etree.SubElement(_body(root, "link3"), "body", name="block")
    etree.SubElement(
        block, "geom", name="block_pla", type="box", size="0.035 0.02 0.02", pos="0.045 0 0", density="1240"
    )


def _steel_inside_a_servo(root) -> None:
    """A steel sphere half inside link2's (solid) servo housing, welded to it."""
    body = etree.SubElement(_body(root, "link2"), "body", name="sunk")
    etree.SubElement(
        body, "geom", name="sunk_steel", type="sphere", size="0.012", pos="0.01 0 0", density="7850"
    )


def cases() -> list[Case]:
    table = [
        ("displaced_counterweight_inertial", "contract.com_mismatch", _displaced_inertial, REFUSED),
        ("steel_one_percent_dense", "contract.point_mass", _dense_steel, REFUSED),
        ("thin_strut_carrying_steel", "contract.overstressed_part", thin_strut, REFUSED),
        ("steel_inside_a_servo", "contract.interpenetration", _steel_inside_a_servo, REFUSED),
        ("part_sunk_into_next_link", "clearance.interpenetration", _sunk_into_next_link, SCORED_DOWN),
    ]
    return [Case(f"physics/f09_{n}", TASK, code, _edit(edit), max_score=cap) for n, code, edit, cap in table]
