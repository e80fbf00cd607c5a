"""Audit cases of family 09, each the reference with one change on every leader alike: hostile MJCF
and meshes (``xml_cases``), physics cheats refused by the contract, hostile trim code
(``code_cases``), generated additions under every stock body, and the workshop rules (issue 45):
unbuildable changes refused by name (every checkpoint of a refused leader scores 0), or scored down
pose by pose with the cause named (a part inside the next link across a joint).

Bounds: a leader that fails loading or its contract skips the submitted-arm battery, but the adapted
reference arm still runs with its trim.py (<= 0.20, ``DESIGN_CAP``); faults of the submitted code keep
motion clearance, the passive battery and servo headroom (<= 0.50, ``CODE_CAP``).
"""

from __future__ import annotations

import re
import shutil
from collections.abc import Callable
from pathlib import Path

import numpy as np
from lxml import etree

from rle_tasks.audit.artifacts import (
    Target,
    actuator,
    edit_xml,
    first_body_attr,
    inject_root,
    inject_worldbody,
    inside_first_body,
    massless,
    weld,
)
from rle_tasks.audit.case import Case
from rle_tasks.audit.code_cases import code_cases
from rle_tasks.audit.generated import Addition, generated_cases
from rle_tasks.audit.xml_cases import xml_cases
from rle_tasks.core.solutions import materialise

TASK = "09-gello"
ROBOTS = ("panda", "ur5e", "xarm7")
TARGET = Target(TASK, xml="lead.xml", bases=ROBOTS, mesh_dir="meshes", code_file="trim.py")
DESIGN_CAP = 0.20
CODE_CAP = 0.50
BODIES = ("base", "link1", "link2", "link3", "link4", "link5", "link6", "tip")
"""Stock bodies the generated additions go under; ``tip`` is each leader's last link (link7, or link6
on the ur5e), so that every leader is altered alike."""
REFUSED = 0.0
"""A leader refused on every robot scores 0 (issue 45: the adapted reference arm's checkpoints too)."""
SCORED_DOWN = 0.9
"""Bound for a case scored pose by pose: below a perfect score (the routed reference itself scores
0.84 quick, with part of its motion-clearance credit)."""


def _spring_attr(attr: str, value: str) -> Callable[[str], str]:
    """Set one attribute of the reference's shoulder spring (the catalog spring becomes an ideal one,
    an under-rated one, or one whose cable would push)."""

    def edit(xml: str) -> str:
        return re.sub(
            rf'(<spatial name="shoulder_spring"[^>]*? {attr}=")[^"]*"', rf'\g<1>{value}"', xml, count=1
        )

    return edit


PHYSICS = [
    ("gravcomp", "contract.gravcomp", first_body_attr('gravcomp="1"')),
    ("gravity_changed", "contract.option_changed", inject_root('<option gravity="0 0 -1"/>')),
    ("timestep_changed", "contract.option_changed", inject_root('<option timestep="0.0001"/>')),
    ("integrator_changed", "contract.option_changed", inject_root('<option integrator="RK4"/>')),
    ("weld_to_world", "contract.world_weld", weld("weld")),
    ("connect_to_world", "contract.world_weld", weld("connect")),
    ("actuator", "contract.actuator", actuator),
    (
        "second_root_body",
        "contract.multiple_roots",
        inject_worldbody('<body name="extra"><geom size="0.01" mass="0.01"/></body>'),
    ),
    ("massless_body", "mjcf.compile", massless),
    (
        "tendon_friction",
        "contract.tendon_friction",
        inject_root(
            '<tendon><fixed name="hold" frictionloss="1.2"><joint joint="j2" coef="1"/></fixed></tendon>'
        ),
    ),
    (
        "tendon_damping",
        "contract.tendon_damping",
        lambda xml: xml.replace(
            '<spatial name="shoulder_spring"', '<spatial name="shoulder_spring" damping="100"', 1
        ),
    ),
    (
        "geom_on_stock_body",
        "contract.stock_body_addition",
        lambda xml: xml.replace(
            '<geom name="link2_shell"',
            '<geom name="dense_extra" type="box" size="0.01 0.01 0.01" density="100000" contype="0" '
            'conaffinity="0"/><geom name="link2_shell"',
            1,
        ),
    ),
    (
        "extra_root_with_joint",
        "contract.extra_joint",
        inject_worldbody(
            '<body name="extra" pos="0.3 0 0.1"><joint name="extra_j" axis="0 1 0"/>'
            '<geom size="0.02" mass="0.1"/></body>'
        ),
    ),
    (
        "floating_counterweight",
        "contract.floating_part",
        lambda xml: re.sub(r'<geom name="counterweight1_rod"[^>]*/>', "", xml, count=1),
    ),
    (
        "spring_end_in_mid_air",
        "contract.spring_anchor",
        lambda xml: xml.replace(
            '<site name="spring_anchor" pos="0 0 0"', '<site name="spring_anchor" pos="0.08 0.08 0.08"', 1
        ),
    ),
    (
        "spring_through_the_arm",
        "contract.spring_path",
        inject_root(
            # a catalog spring on a slack cable: only its path is at fault
            '<tendon><spatial name="long_spring" stiffness="717.05" springlength="0 2">'
            '<site site="mount_site"/><site site="handle_site"/></spatial></tendon>'
        ),
    ),
    ("ideal_spring", "contract.spring_catalog", _spring_attr("stiffness", "950")),
    ("overloaded_spring", "contract.spring_overload", _spring_attr("stiffness", "939.852")),
    ("pushing_spring", "contract.spring_push", _spring_attr("springlength", "0.03")),
    (
        "ideal_torsion_spring",
        "contract.spring_catalog",
        lambda xml: xml.replace('<joint name="j2"', '<joint name="j2" stiffness="0.5"', 1),
    ),
    (
        "weightless_strut",
        "contract.underweight_part",
        inside_first_body('<body name="strut"><geom type="box" size="0.05 0.01 0.01" mass="0.0001"/></body>'),
    ),
    (
        "negative_inertia",
        "contract.invalid_inertia",
        inside_first_body('<body name="neg"><inertial pos="0 0 0" mass="0.1" diaginertia="-1 1 1"/></body>'),
    ),
    (
        "impossible_inertia",
        "contract.invalid_inertia",
        inside_first_body(
            '<body name="odd"><inertial pos="0 0 0" mass="0.1" diaginertia="1e-4 1e-4 1"/></body>'
        ),
    ),
]
"""Physics cheats: (name, expected code, edit of lead.xml)."""


def expected(a: Addition) -> tuple[str, ...]:
    """Codes a generated addition must produce (the first is the corpus case's code). A body's PLA
    sphere sits at its link's origin, inside the solid servo housing it is welded to: a part inside
    another (issue 45); under the base it sits in the plate's open underside and is accounted for."""
    inside = () if a.body == "base" else ("contract.interpenetration",)
    return {"geom": ("contract.stock_body_addition",), "body": inside, "joint": ("contract.extra_joint",)}[
        a.kind
    ]


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
    """Family 09's cases (``rle audit-verifiers``)."""
    table = [
        ("displaced_counterweight_inertial", "contract.com_mismatch", _displaced_inertial, REFUSED),
        ("steel_one_percent_dense", "contract.point_mass", _dense_steel, REFUSED),
        ("thin_strut_carrying_steel", "contract.overstressed_part", thin_strut, REFUSED),
        ("steel_inside_a_servo", "contract.interpenetration", _steel_inside_a_servo, REFUSED),
        ("part_sunk_into_next_link", "clearance.interpenetration", _sunk_into_next_link, SCORED_DOWN),
    ]
    out = xml_cases(TARGET, DESIGN_CAP)
    out.append(Case("artifact/f09_empty_dir", TASK, "artifact.missing_robot", lambda d: d))
    out += [
        Case(f"physics/f09_{n}", TASK, code, edit_xml(TARGET, edit), max_score=DESIGN_CAP)
        for n, code, edit in PHYSICS
    ]
    out += code_cases(TARGET, "feedforward", "a[0]", CODE_CAP)
    out += generated_cases(TARGET, BODIES, expected, DESIGN_CAP)
    return out + [
        Case(f"physics/f09_{n}", TASK, code, _edit(edit), max_score=cap) for n, code, edit, cap in table
    ]
