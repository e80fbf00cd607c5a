"""Generated additions for the design families: whatever a submission adds is accounted or refused.

For family 08 (the base) and family 09 (each leader) the generator adds, under every stock body,

* a geom (a dense 20 mm box that collides with nothing);
* a child body carrying a 10 mm PLA sphere at the body's origin (one more level of the tree);
* a child body with a joint of each type (hinge, slide, ball, free).

Each addition is either allowed by the contract and accounted for (family 09: a welded PLA part, its
mass counted in the device mass) or refused with a named code (``EXPECTED``). ``additions`` lists them
for the unit tests (tests/f08_mobile_base, tests/f09_gello); ``generated_cases`` turns the refusals into corpus cases.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from lxml import etree

from rle_tasks.audit.case import Case

JOINT_TYPES = ("hinge", "slide", "ball", "free")
F08_BODIES = ("chassis", "wheel_fl", "wheel_fr", "wheel_rl", "wheel_rr", "battery", "universal_adapter")
F09_BODIES = ("base", "link1", "link2", "link3", "link4", "link5", "link6", "tip")
"""Stock bodies of the leaders; ``tip`` is each leader's last link (link7, or link6 on the ur5e), so
that every leader is altered alike."""
GEOM_NAME, BODY_NAME, JOINT_BODY_NAME = "generated_geom", "generated_body", "generated_joint_body"
PLA_SPHERE_R = 0.01  # [m]


@dataclass(frozen=True)
class Addition:
    """One generated addition.

    Attributes:
        body: The stock body it goes under.
        kind: ``"geom"``, ``"body"`` or ``"joint"``.
        joint: The joint type for ``kind == "joint"``.
    """

    body: str
    kind: str
    joint: str = ""

    @property
    def name(self) -> str:
        what = {"geom": "geom_on", "body": "body_under"}.get(self.kind, f"{self.joint}_joint_under")
        return f"{what}_{self.body}"

    def apply(self, root: etree._Element) -> bool:
        """Add it to an MJCF tree; False when the tree has no such body."""
        name = self.body
        if name == "tip":  # the last link of a leader: link<n> with the largest n
            links = [
                b.get("name") for b in root.iter("body") if re.fullmatch(r"link\d+", b.get("name") or "")
            ]
            name = max(links, key=lambda s: int(s[4:]), default="")
        body = next((b for b in root.iter("body") if b.get("name") == name), None)
        if body is None:
            return False
        if self.kind == "geom":
            etree.SubElement(
                body, "geom", name=GEOM_NAME, type="box", size="0.01 0.01 0.01", density="100000",
                contype="0", conaffinity="0",
            )  # fmt: skip
            return True
        child = etree.SubElement(body, "body", name=BODY_NAME if self.kind == "body" else JOINT_BODY_NAME)
        if self.kind == "joint":
            if self.joint == "free":
                etree.SubElement(child, "freejoint", name="generated_joint")
            else:
                etree.SubElement(child, "joint", name="generated_joint", type=self.joint)
        etree.SubElement(
            child, "geom", name=f"{child.get('name')}_pla", type="sphere", size=f"{PLA_SPHERE_R}",
            density="1240", contype="0", conaffinity="0",
        )  # fmt: skip
        return True

    def edit_text(self, xml: str) -> str:
        root = etree.fromstring(xml.encode())
        self.apply(root)
        return etree.tostring(root, encoding="unicode")


def additions(bodies: tuple[str, ...]) -> list[Addition]:
    out = []
    for b in bodies:
        out += [Addition(b, "geom"), Addition(b, "body")] + [Addition(b, "joint", j) for j in JOINT_TYPES]
    return out


def expected(task: str, a: Addition) -> tuple[str, ...]:
    """Codes the addition must produce (the first is the corpus case's code); () when it is allowed
    and accounted for."""
    if a.kind == "joint" and a.joint == "free":
        return ("mjcf.compile",)  # MuJoCo: a free joint only on a root body
    if task == "09-gello":
        # a body's PLA sphere sits at its link's origin, inside the solid servo housing it is welded
        # to: a part inside another (issue 45); under the base it sits in the plate's open underside
        inside = () if a.body == "base" else ("contract.interpenetration",)
        return {
            "geom": ("contract.stock_body_addition",),
            "body": inside,
            "joint": ("contract.extra_joint",),
        }[a.kind]
    if a.kind == "geom":
        return ("catalog.non_catalog_mass",) if a.body == "chassis" else ("f08.part_modified",)
    if a.kind == "body":
        return ("f08.extra_body",)
    return ("f08.extra_joints", "f08.extra_body")


def generated_cases(
    task: str, edit_xml: Callable[[str, Callable[[str], str]], Callable[[Path], Path]], max_score: float
) -> list[Case]:
    """Corpus cases of every refused addition of ``task`` (``edit_xml`` as in ``corpus.py``)."""
    bodies = F09_BODIES if task == "09-gello" else F08_BODIES
    fam = task[:2]
    out = []
    for a in additions(bodies):
        codes = expected(task, a)
        if codes:
            cap = 0.0 if codes[0] == "mjcf.compile" and fam == "08" else max_score
            out.append(
                Case(f"generated/f{fam}_{a.name}", task, codes[0], edit_xml(task, a.edit_text), max_score=cap)
            )
    return out
