"""Generated additions for the design families: whatever a submission adds is accounted or refused.

A design family (08: the base, 09: each leader) names its stock bodies and the codes each addition
must produce (its ``audit.py``); the generator adds, under every stock body,

* a geom (a dense 20 mm box that collides with nothing);
* a child body carrying a 10 mm PLA sphere at the body's origin (one more level of the tree);
* a child body with a joint of each type (hinge, slide, ball, free).

Each addition is either allowed by the contract and accounted for (family 09: a welded PLA part, its
mass counted in the device mass) or refused with a named code. ``additions`` lists them for the unit
tests (tests/f08_mobile_base, tests/f09_gello); ``generated_cases`` turns the refusals into corpus
cases.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass

from lxml import etree

from rle_tasks.audit.artifacts import Target, edit_xml
from rle_tasks.audit.case import Case

JOINT_TYPES = ("hinge", "slide", "ball", "free")
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


def codes(a: Addition, expected: Callable[[Addition], tuple[str, ...]]) -> tuple[str, ...]:
    """Codes ``a`` must produce: the family's ``expected(a)``, but a free joint under a body is refused
    by MuJoCo's compiler (``mjcf.compile``: a free joint only on a root body)."""
    return ("mjcf.compile",) if a.kind == "joint" and a.joint == "free" else expected(a)


def generated_cases(
    target: Target,
    bodies: tuple[str, ...],
    expected: Callable[[Addition], tuple[str, ...]],
    max_score: float,
    compile_cap: float | None = None,
) -> list[Case]:
    """Corpus cases of every refused addition under ``bodies``: ``expected(a)`` gives the codes an
    addition must produce (the first is the case's code; () when it is allowed and accounted for).
    Cases refused by MuJoCo's compiler are bounded by ``compile_cap`` when given."""
    out = []
    for a in additions(bodies):
        refused = codes(a, expected)
        if refused:
            cap = compile_cap if refused[0] == "mjcf.compile" and compile_cap is not None else max_score
            name = f"generated/f{target.task[:2]}_{a.name}"
            out.append(Case(name, target.task, refused[0], edit_xml(target, a.edit_text), max_score=cap))
    return out
