"""The reference leaders' design (build time only; ``build`` writes them, ``attached`` fastens them).

Reference (``solutions/reference/<robot>/lead.xml``), derivation (``exact_design``):

1. Counterweights tip-first: for joints n..3 the subtree beyond the joint (already balanced) has
   mass M and centre-of-mass offset d from the joint axis; a steel sphere of m_c = M |d| / r_c at
   r_c = ``EXACT_RADIUS`` opposite d (shifted ``CW_AXIAL`` along the axis to sweep free space) puts
   the subtree's centre of mass on the axis, so the joint carries no gravity torque at any pose.
2. Joint 1 is vertical; joint 2 then carries a rigid body of fixed centre of mass: an ideal
   zero-length spring (tendon ``springlength="0"``) from ``SPRING_ARM`` above joint 2 on link 1 to
   ``SPRING_ARM`` along the centre-of-mass direction on link 2 with k a b = M g |d| balances it
   exactly at every angle (residual ~1e-8 N m from the 9-digit XML numbers).
3. Fastening (``attached.py``, ``placement_search.py``, ``rebalance.py``): each counterweight on an
   aluminium rod from its link's shell (or servo housing) or on an L-bracket, each spring end on an
   aluminium post, placements chosen greedily for clearance as the verifier counts it (collisions,
   spring paths through parts, and parts inside the next link across a joint,
   ``rle_design.mjcf.interpenetration``); the ideal spring becomes the catalog spring nearest in rate
   (``rle_design/catalogs/springs.yaml``), then masses, centres and the spring's attachment point
   re-optimised with the rods and posts counted (``rle_design.kinematics.codesign``, CasADi/IPOPT).
4. ``trim.py`` (shared by the three robots) fits the identifiable gravity parameters (QR base
   parameters of the Pinocchio regressor) to the 16 probes with a small ridge to the nominal values,
   after a greedy D-optimal probe plan over a candidate grid; hidden link-mass and payload changes
   are then carried by the servos.

The baselines are declared beside the reference in ``solutions/__init__.py``.
"""

from __future__ import annotations

import shutil
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np
from lxml import etree

from rle_tasks.f09_gello.device import ASSET_DIR, STEEL_DENSITY

PKG = Path(__file__).resolve().parents[1]
AXIAL_MAX = 0.12
CW_AXIAL = 0.055
EXACT_RADIUS = 0.10
MASS_CAP = 2.1
SPRING_ARM = 0.05
SPRING_OFFSET = 0.03


@dataclass(frozen=True)
class Design:
    """Passive elements of one leader.

    Attributes:
        counterweights: ``(link body, position in its frame [m], mass [kg])`` per steel sphere.
        spring: ``(body, anchor [m], body, attachment [m], stiffness [N/m])`` of a zero-length spring.
        torsion: ``(joint, stiffness [N m/rad], rest angle [rad])`` per torsion spring.
        unbalanced: Joint k -> gravity moment of its subtree [N m], for each joint k >= 3 left
            without a counterweight (the servo carries it).
    """

    counterweights: tuple[tuple[str, tuple[float, float, float], float], ...]
    spring: tuple[str, tuple[float, ...], str, tuple[float, ...], float] | None
    torsion: tuple[tuple[str, float, float], ...]
    unbalanced: dict[int, float] | None = None


def _rot(quat: np.ndarray) -> np.ndarray:
    r = np.zeros(9)
    mujoco.mju_quat2Mat(r, quat)
    return r.reshape(3, 3)


def exact_design(
    robot: str,
    placement: dict[int, tuple | None] | None = None,
    spring_axial: tuple[float, float] = (SPRING_OFFSET, SPRING_OFFSET),
    spring_side: int = 1,
) -> Design:
    """Exact static balance: counterweights tip-first on joints 3..n, zero-length spring on joint 2.

    Working from the handle towards the base, the subtree beyond joint k (its link, everything
    distal, already balanced) has mass M and first moment S in link k's frame. A steel counterweight
    of mass m_c = M |d| / r_c at -r_c d/|d| (d = S_xy / M, the centre of mass's offset from the joint
    axis; shifted ``axial`` along the axis so it sweeps free space) puts the subtree's centre of mass
    on the axis: joint k then carries no gravity torque at any pose, and the subtree acts on the
    joints above it as a point mass fixed on axis k. Joint 1 is vertical (never loaded). Joint 2 is
    horizontal and carries a rigid body of fixed centre of mass: a zero-length spring from a point
    ``SPRING_ARM`` straight above joint 2 (on link 1) to a point ``SPRING_ARM`` along the centre-of-mass
    direction (on link 2) with k a b = M g |d| balances it exactly at every angle.

    Args:
        robot: Follower id.
        placement: Joint k -> (r_c [m], axial shift [m]) of its counterweight, or None for no
            counterweight on joint k; default (``EXACT_RADIUS``, ``CW_AXIAL``). An axial shift of
            None puts the balanced subtree's centre of mass where axis k passes nearest axis k - 1
            (on it where they cross, as at panda's wrist): joint k - 1 then carries only its own
            link's moment and may do without a counterweight. A third number s splits the weight
            into a pair, each half the mass, at the axial shift +- s [m]: the same first moment, so
            the same balance, but astride the plane in which a single weight would swing through
            the link beyond joint k - 1 (a yoke).
        spring_axial: Offsets of the spring's anchor and attachment along joint 2's axis [m]: a
            zero-length spring's torque about the axis does not depend on them (its energy
            k |a - R b|^2 / 2 changes by a constant), so they only move the posts clear of the links
            and of each other.
        spring_side: +1, the anchor above joint 2 and the attachment along the centre-of-mass
            direction; -1, the anchor below joint 2 and the attachment opposite it (the same
            k a . R b, so the same balance), which keeps the anchor's post out of the folded
            forearm's sweep.
    """
    placement = placement or {}
    m = mujoco.MjModel.from_xml_path(str(ASSET_DIR / robot / "lead.xml"))
    n = m.nv
    child_m, child_s = 0.0, np.zeros(3)
    cws = []
    spring = None
    unbalanced = {}
    g = float(np.linalg.norm(m.opt.gravity))
    for k in range(n, 1, -1):
        b = m.body(f"link{k}").id
        mass = float(m.body_mass[b]) + child_m
        first = m.body_mass[b] * m.body_ipos[b]
        if k < n:
            c = m.body(f"link{k + 1}").id
            first = first + _rot(m.body_quat[c]) @ child_s + child_m * m.body_pos[c]
        d = first[:2] / mass
        off = float(np.linalg.norm(d))
        if k >= 3 and off > 1e-9 and placement.get(k, ()) is not None:
            u = np.array([d[0], d[1], 0.0]) / off
            radius, axial, *spread = placement.get(k, (EXACT_RADIUS, CW_AXIAL))
            mc = mass * off / radius
            if axial is None:  # nearest point of axis k to axis k - 1, in link k's frame
                o, e = m.body_pos[b], _rot(m.body_quat[b])[:, 2]
                z = -float(o[:2] @ e[:2]) / max(float(e[:2] @ e[:2]), 1e-12)
                axial = float(np.clip((z * (mass + mc) - first[2]) / mc, -AXIAL_MAX, AXIAL_MAX))
            pos = -radius * u + np.array([0.0, 0.0, axial])
            for dz in (spread[0], -spread[0]) if spread else (0.0,):
                part = pos + np.array([0.0, 0.0, dz])
                cws.append((f"link{k}", tuple(float(x) for x in part), mc / (2 if spread else 1)))
            first = first + mc * pos
            mass += mc
        elif k >= 3:
            unbalanced[k] = g * mass * off
        elif k == 2:
            b1, b2 = m.body("link1").id, m.body("link2").id
            axis1 = _rot(m.body_quat[b2])[:, 2]
            up = np.array([0.0, 0.0, 1.0]) - axis1 * axis1[2]
            up /= np.linalg.norm(up)
            anchor = m.body_pos[b2] + spring_side * SPRING_ARM * up + spring_axial[0] * axis1
            attach = spring_side * SPRING_ARM * np.array([d[0], d[1], 0.0]) / off + np.array(
                [0.0, 0.0, spring_axial[1]]
            )
            stiffness = mass * g * off / (SPRING_ARM * SPRING_ARM)
            spring = (
                "link1",
                tuple(float(x) for x in anchor),
                "link2",
                tuple(float(x) for x in attach),
                stiffness,
            )
            del b1
        child_m, child_s = mass, first
    return Design(tuple(cws), spring, (), unbalanced)


def _fmt(v) -> str:
    return " ".join(f"{float(x):.9g}" for x in np.ravel(v))


def add_spring_tendon(root, k: float) -> None:
    """The zero-length shoulder spring of stiffness ``k`` [N/m] between the sites ``spring_anchor`` and
    ``spring_attach`` (a spatial tendon appended to the MJCF ``root``)."""
    tendon = etree.SubElement(root, "tendon")
    sp = etree.SubElement(
        tendon,
        "spatial",
        name="shoulder_spring",
        stiffness=f"{k:.9g}",
        springlength="0",
        width="0.002",
        rgba="0.2 0.6 0.9 1",
    )
    etree.SubElement(sp, "site", site="spring_anchor")
    etree.SubElement(sp, "site", site="spring_attach")


def apply_design(robot: str, design: Design, out_dir: Path) -> Path:
    """Write the stock leader with the design's elements added into ``out_dir``."""
    src = ASSET_DIR / robot
    if out_dir.exists():
        shutil.rmtree(out_dir)
    shutil.copytree(src, out_dir)
    tree = etree.parse(str(out_dir / "lead.xml"))
    root = tree.getroot()

    def body(name: str):
        return next(b for b in root.iter("body") if b.get("name") == name)

    for k, (link, pos, mass) in enumerate(design.counterweights):
        radius = (3 * mass / (4 * np.pi * STEEL_DENSITY)) ** (1 / 3)
        cw = etree.SubElement(body(link), "body", name=f"counterweight{k + 1}", pos=_fmt(pos))
        etree.SubElement(
            cw,
            "geom",
            name=f"counterweight{k + 1}_steel",
            type="sphere",
            size=f"{radius:.9g}",
            mass=f"{mass:.9g}",
            rgba="0.5 0.5 0.55 1",
        )
    if design.spring is not None:
        l1, p1, l2, p2, k = design.spring
        etree.SubElement(body(l1), "site", name="spring_anchor", pos=_fmt(p1), size="0.004")
        etree.SubElement(body(l2), "site", name="spring_attach", pos=_fmt(p2), size="0.004")
        add_spring_tendon(root, k)
    for jname, k, ref in design.torsion:
        j = next(e for e in root.iter("joint") if e.get("name") == jname)
        j.set("stiffness", f"{k:.9g}")
        j.set("springref", f"{ref:.9g}")
    etree.indent(tree, space="  ")
    path = out_dir / "lead.xml"
    tree.write(str(path), xml_declaration=False, encoding="utf-8")
    return path


PLACEMENTS = (
    ((0.05, 0.0), (0.08, 0.0))
    + tuple(
        (r, s * a)
        for r in (0.05, 0.08, 0.10, 0.12, 0.15)
        for a in (0.035, CW_AXIAL, 0.08, 0.105)
        for s in (1, -1)
    )
    + ((0.035, 0.0), (0.04, 0.0), (0.04, 0.035), (0.04, -0.035), None)
    + tuple((r, None) for r in (0.05, 0.08, 0.10, 0.12, 0.15))
    + tuple((r, None, s) for r in (0.05, 0.08, 0.10, 0.12) for s in (0.035, 0.055))
)
"""Counterweight options of the greedy placement: (radius from the joint axis, axial shift) [m], the
compact 35-40 mm ones (heavier, but they stay inside the links' sweep), an axial shift that unloads
the joint before (None, ``exact_design``), alone or as a pair astride that height (a third number,
the pair's axial spread), or None (no counterweight on that joint: its subtree's
gravity moment stays with the servo)."""
