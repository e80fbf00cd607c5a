"""Build-time: the reference leaders' added parts fastened to their links (build time only).

``exact_design`` (``design.py``) places steel counterweights and a zero-length spring where they
balance the arm exactly, but leaves them in mid-air. Here each element is fastened to its link
(``fasten``, written by ``write_leader``):

* a counterweight hangs on an aluminium rod (cylinder, ``ARM_RADIUS``) from the nearest point of its
  link's material (``EMBED`` inside it) to the sphere's centre; the rod's mass is counted. Or it sits
  on an L-bracket (``BRACKETS``): a post rises from the link's material nearest its top, which stands
  out along the link or beside it at the sphere's axial height, and the rod runs from the post's top
  to the sphere, so it sweeps a disc beside the neighbouring link instead of through it. A pair of
  half weights astride a joint's plane (``design.PLACEMENTS``) gets a rod or bracket each: a wrist
  weight whose centre of mass must lie on the axis before (so that joint needs none) then swings
  beside the forearm instead of through it;
* each spring end sits on the end face of an aluminium post (``BRACKET_RADIUS``) from the nearest
  point of its link's material (``EMBED`` inside) to the spring site, or, for the anchor, on an
  L-post that leaves link 1 below the shoulder and rises beside link 2's sweep (``SPRING_OPTIONS``).

The rest of the build: the catalog spring and the re-balance with rods and posts counted
(``rebalance.py``), the score a placement loses (``placement_loss.py``), the verifier's findings for
a candidate (``part_checks.py``), the joint search's parameters and estimate (``joint_search.py``),
and the placement search that chooses every mount (``placement_search.clear_fastened``).
"""

from __future__ import annotations

import shutil
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np
from lxml import etree

from rle_tasks.f09_gello.device import ASSET_DIR, STEEL_DENSITY
from rle_tasks.f09_gello.solutions.design import add_spring_tendon

ROD_DENSITY = 2700.0
"""Rods and posts are aluminium 6063 bar [kg/m^3] (``materials.yaml``), threaded into the printed links:
an 8 mm aluminium rod weighs what a 12 mm PLA rod does (0.136 against 0.140 kg/m) but is four times
stiffer (E I) and four times as strong (97 against 25 MPa allowable), and thinner, so it clears the
neighbouring links more often."""
ARM_RADIUS = 0.004
"""Counterweight rod and L-bracket post radius [m]: 8 mm aluminium. The routed build's panda wrist weight
(0.43 kg on a 168 mm rod): 28 MPa against 97 MPa allowable, 0.5 mm sag (2 % is 3.4 mm); the build
refuses any placement with a strength finding (``structure_faults``). (12 mm PLA rods
before issue 45's routing; 10 mm PLA ones sagged 2.4 % of their span, ``contract.flexible_part``.)"""
BRACKET_RADIUS = 0.006
"""Spring post radius [m]: 12 mm aluminium. An anchor L-post's 28 mm foot carrying 98 N of spring
(the heaviest exact design the build tries) 80 mm below the anchor bends to 64 MPa, within
aluminium's 97 MPa allowable (``contract.overstressed_part``: 145 MPa / 1.5)."""
EMBED = 0.002
"""Printed parts reach this far into the part they are fastened to [m]."""
BRACKETS = ((0.04, 0.0), (0.07, 0.0), (0.03, 0.05), (0.03, -0.05))
"""Where an L-bracket's post stands, the greedy's options [m]: (along the link, towards its centre of
mass and away from the weight; across, perpendicular to it and to the joint axis). Along the link the
post rises from the link's tube beyond the ~20 mm radius of the neighbouring link's tube that ends at
the joint, and the rod crosses the axis at the weight's height; beside it the rod passes 30-40 mm
from the axis, clear of a neighbouring tube that runs along the axis (a roll joint)."""
SPRING_OPTIONS = tuple(
    (s * za, s * zb, drop)
    for s in (1, -1)
    for za, zb in ((0.03, 0.03), (0.045, 0.025), (0.055, 0.03), (0.055, 0.035), (0.07, 0.035))
    for drop in (None, 0.0, 0.03)
)
"""Spring mounts the build chooses from: anchor and attachment offsets along joint 2's axis [m] (the
balance does not depend on them, ``design.exact_design``) and the anchor post's route: None, a
straight post from the nearest material of link 1; a drop d [m], an L-post that leaves link 1's tube
at d below joint 2 and rises parallel to link 1, beside the shoulder servo rather than through it."""
SPRING_DESCENT = tuple(
    (s * za, s * zb, drop, side)
    for side in (1, -1)
    for s in (1, -1)
    for za, zb in ((0.03, 0.03), (0.045, 0.025), (0.055, 0.03), (0.07, 0.035), (0.09, 0.035), (0.09, 0.05))
    for drop in ((None, 0.0, 0.03) if side > 0 else (None,))
)
"""Further spring mounts the coordinate descent (``clear_fastened``'s ``descent``) tries: a fourth
number -1 puts the anchor below joint 2 and the attachment opposite link 2's centre of mass
(``design.exact_design``'s ``spring_side``: the same balance), on a straight post from link 1's side,
out of the folded forearm's sweep; and anchors farther out along joint 2's axis (90 mm)."""


@dataclass(frozen=True)
class Fastened:
    """One leader's passive elements with their printed mounts (positions in the link frames) [m, kg].

    Attributes:
        counterweights: ``(link, centre, mass, rod start)`` per steel sphere.
        spring: ``(link, anchor, post start, link, attachment, post start, stiffness [N/m])`` or None.
        posts: Per counterweight, its L-bracket post ``(start in the link, top)`` (the rod then
            starts at the top), or None for a straight rod.
        anchor_elbow: The spring anchor post's bend (link 1 frame): the post runs from its start to
            the elbow, then to the anchor; None for a straight post.
    """

    counterweights: tuple[tuple[str, np.ndarray, float, np.ndarray], ...]
    spring: tuple[str, np.ndarray, np.ndarray, str, np.ndarray, np.ndarray, float] | None
    posts: tuple[tuple[np.ndarray, np.ndarray] | None, ...] = ()
    anchor_elbow: np.ndarray | None = None


def _fmt(v) -> str:
    return " ".join(f"{float(x):.9g}" for x in np.ravel(v))


def nearest_on_body(
    xml: Path, body: str, point: np.ndarray, shell_only: bool = True, embed: float = EMBED
) -> np.ndarray:
    """Nearest point of ``body``'s material to ``point`` (body frame, qpos0), ``embed`` inside [m].

    With ``shell_only`` (and a ``*_shell`` geom on the body) only the printed shell counts; otherwise
    any geom of the body (the servo housing too)."""
    spec = mujoco.MjSpec.from_file(str(xml))
    b = spec.body(body)
    b.add_geom(
        name="__probe__",
        type=mujoco.mjtGeom.mjGEOM_SPHERE,
        size=[1e-4, 0, 0],
        pos=point,
        contype=0,
        conaffinity=0,
    )
    m = spec.compile()
    d = mujoco.MjData(m)
    mujoco.mj_kinematics(m, d)
    bid = m.body(body).id
    probe = m.geom("__probe__").id
    own = [g for g in range(m.ngeom) if g != probe and m.geom_bodyid[g] == bid]
    # the printed shell is what a part is screwed to; the servo sits inside the neighbouring links
    shells = [g for g in own if (mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, g) or "").endswith("_shell")]
    best, best_pt = np.inf, None
    for g in shells if shell_only and shells else own:
        fromto = np.zeros(6)
        dist = mujoco.mj_geomDistance(m, d, probe, g, 1.0, fromto)
        if dist < best:
            best, best_pt = dist, fromto[3:].copy()
    if best_pt is None:
        raise ValueError(f"body '{body}' has no geometry to fasten to")
    rot = d.xmat[bid].reshape(3, 3)
    local = rot.T @ (best_pt - d.xpos[bid])
    approach = local - np.asarray(point, float)
    n = np.linalg.norm(approach)
    return local + (embed * approach / n if n > 1e-9 else 0.0)


def write_leader(robot: str, design: Fastened, out_dir: Path, *, with_counterweights: bool = True) -> Path:
    """Write the stock leader of ``robot`` with ``design``'s fastened elements into ``out_dir``."""
    if out_dir.exists():
        shutil.rmtree(out_dir)
    shutil.copytree(ASSET_DIR / robot, out_dir)
    tree = etree.parse(str(out_dir / "lead.xml"))
    root = tree.getroot()

    def body(name: str):
        return next(b for b in root.iter("body") if b.get("name") == name)

    def rod(parent, name: str, start: np.ndarray, end: np.ndarray, radius: float) -> None:
        etree.SubElement(
            parent,
            "geom",
            name=name,
            type="cylinder",
            fromto=_fmt(np.concatenate([start, end])),
            size=f"{radius:.9g}",
            density=f"{ROD_DENSITY:.9g}",
            rgba="0.75 0.77 0.8 1",
        )

    posts = design.posts or (None,) * len(design.counterweights)
    holders = {}  # counterweight -> (its L-bracket's post body, the post's top in the link frame)
    for k, ((link, *_), post) in enumerate(zip(design.counterweights, posts, strict=True), 1):
        if post is not None:  # the L-bracket's post is structure of the link: written even without weights
            start, top = post
            holder = etree.SubElement(body(link), "body", name=f"counterweight{k}_post", pos=_fmt(top))
            rod(holder, f"counterweight{k}_post_al", np.asarray(start) - top, np.zeros(3), ARM_RADIUS)
            holders[k] = (holder, np.asarray(top))
    if with_counterweights:
        for k, (link, centre, mass, start) in enumerate(design.counterweights, 1):
            radius = (3 * mass / (4 * np.pi * STEEL_DENSITY)) ** (1 / 3)
            # on an L-bracket the weight's rod hangs from the post's top: the post is its parent body
            parent, origin = holders.get(k, (body(link), np.zeros(3)))
            cw = etree.SubElement(
                parent, "body", name=f"counterweight{k}", pos=_fmt(np.asarray(centre) - origin)
            )
            etree.SubElement(
                cw,
                "geom",
                name=f"counterweight{k}_steel",
                type="sphere",
                size=f"{radius:.9g}",
                mass=f"{mass:.9g}",
                rgba="0.5 0.5 0.55 1",
            )
            rod(cw, f"counterweight{k}_rod", np.asarray(start) - centre, np.zeros(3), ARM_RADIUS)
    if design.spring is not None:
        l1, p1, s1, l2, p2, s2, k = design.spring
        for name, link, site, start in (("anchor", l1, p1, s1), ("attach", l2, p2, s2)):
            post = etree.SubElement(body(link), "body", name=f"spring_{name}_post", pos=_fmt(site))
            elbow = design.anchor_elbow if name == "anchor" else None
            if elbow is None:
                rod(post, f"spring_{name}_post_al", np.asarray(start) - site, np.zeros(3), BRACKET_RADIUS)
            else:
                bend = np.asarray(elbow) - site
                rod(post, f"spring_{name}_foot_al", np.asarray(start) - site, bend, BRACKET_RADIUS)
                rod(post, f"spring_{name}_post_al", bend, np.zeros(3), BRACKET_RADIUS)
            etree.SubElement(post, "site", name=f"spring_{name}", pos="0 0 0", size="0.004")
        add_spring_tendon(root, k)
    etree.indent(tree, space="  ")
    path = out_dir / "lead.xml"
    tree.write(str(path), xml_declaration=False, encoding="utf-8")
    return path


def fasten(
    robot: str,
    exact,
    servo_mount: frozenset[str] = frozenset(),
    bracket: dict[str, tuple[float, float]] | None = None,
    anchor_drop: float | None = None,
    flush: frozenset[str] = frozenset(),
) -> Fastened:
    """Mounts for an ``exact_design``: rods to each counterweight, posts under each spring end.

    A rod starts on its link's printed shell, or on any of the link's geoms (the servo housing) for
    the links in ``servo_mount``; for the links in ``bracket`` (link -> ``BRACKETS`` entry) it
    starts on the top of an L-bracket's post that rises from the link's nearest material. The
    spring anchor's post is straight, or bent ``anchor_drop`` below joint 2 (``SPRING_OPTIONS``). A
    straight rod on a link in ``flush`` starts on its link's surface instead of ``EMBED`` inside it. The
    masses and stiffness are still the exact (mid-air) ones; ``optimise`` re-balances them.
    """
    stock = ASSET_DIR / robot / "lead.xml"
    bracket = bracket or {}
    cws, posts = [], []
    for link, pos, mass in exact.counterweights:
        centre = np.asarray(pos, float)
        if link in bracket:
            along = -centre[:2] / np.linalg.norm(centre[:2])  # towards the link's centre of mass
            across = np.array([-along[1], along[0]])
            reach, side = bracket[link]
            top = np.array([*(reach * along + side * across), centre[2]])
            # the post rises from the material nearest its top: along the joint axis from the side
            # of a link that runs across the axis, so it stays out of the neighbouring link's sweep
            posts.append((nearest_on_body(stock, link, top, shell_only=link not in servo_mount), top))
            cws.append((link, centre, float(mass), top))
        else:
            posts.append(None)
            embed = 0.0 if link in flush else EMBED
            start = nearest_on_body(stock, link, centre, shell_only=link not in servo_mount, embed=embed)
            cws.append((link, centre, float(mass), start))
    spring, elbow = None, None
    if exact.spring is not None:
        l1, p1, l2, p2, k = exact.spring
        p1, p2 = np.asarray(p1, float), np.asarray(p2, float)
        start1 = None
        if anchor_drop is not None:
            m = mujoco.MjModel.from_xml_path(str(stock))
            b2 = m.body(l2)
            axis = np.zeros(9)
            mujoco.mju_quat2Mat(axis, b2.quat)
            axis = axis.reshape(3, 3)[:, 2]
            rel = p1 - b2.pos
            up = rel - axis * (axis @ rel)  # the anchor's arm, across joint 2's axis
            elbow = p1 - up - anchor_drop * up / np.linalg.norm(up)
            start1 = nearest_on_body(stock, l1, elbow)
        else:
            start1 = nearest_on_body(stock, l1, p1)
        spring = (l1, p1, start1, l2, p2, nearest_on_body(stock, l2, p2), float(k))
    return Fastened(tuple(cws), spring, tuple(posts), elbow)
