"""Kinematic tables of the three followers and the CAD assembly of their scaled GELLO leaders.

Derivation (numbered as in the family README):

1. Follower kinematics: UR5e standard DH (d1 .1625, a2 -.425, a3 -.3922, d4 .1333, d5 .0997,
   d6 .0996); Panda modified DH (d1 .333, d3 .316, a4 .0825, a5 -.0825, d5 .384, a7 .088, flange
   .107); xArm7 modified DH (d1 .267, d3 .293, a3 .0525, a4 .0775, d5 .3425, a6 .076, d7 .097).
2. Every length is multiplied by ``SCALE`` = 0.55 (the real UR5 GELLO is ~0.55x its follower by
   STL bounding box), so leader joint frames are the follower's frames scaled about the base.
3. Each link is a printed PLA tube from its joint to the next one (outer radius ``LinkStyle.radius``,
   wall ``LinkStyle.wall``), mass = shell volume x PLA density; an XL330-M288-T servo body (18 g,
   20 x 34 x 26 mm) sits on every joint; the last link carries a printed handle grip; the base is a
   printed mount plate bolted to the table (no joint).
4. Joint friction, damping and armature come from the servo catalog (Coulomb friction ->
   ``frictionloss``, viscous -> ``damping``, reflected inertia -> ``armature``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rle_design.catalog import load_catalog
from rle_design.scene import arm_ids

SCALE = 0.55
ROBOTS: tuple[str, ...] = arm_ids()
"""Followers with a leader: the arms of the catalog (``arms`` kind), in catalog order."""
SERVO_ID = "XL330-M288-T"
PLA_ID = "pla"


@dataclass(frozen=True)
class LinkStyle:
    """Printed link style.

    Attributes:
        radius: Outer tube radius [m].
        wall: Printed wall thickness [m] (0.4 mm nozzle, 6 perimeters = 2.4 mm).
        handle_length: Handle grip length [m].
        handle_radius: Handle grip outer radius [m].
    """

    radius: float = 0.016
    wall: float = 0.0024
    handle_length: float = 0.10
    handle_radius: float = 0.016


@dataclass(frozen=True)
class Leader:
    """Kinematics of one leader (already scaled).

    Attributes:
        robot: Follower id.
        body_pos: Position of body i in its parent's frame at q = 0 [m], one per joint.
        body_rot: Rotation of body i in its parent's frame (3x3), one per joint.
        flange: Flange point in the last body's frame [m].
        ranges: Joint limits [rad], shape (n, 2).
        style: Printed link style.
    """

    robot: str
    body_pos: tuple[np.ndarray, ...]
    body_rot: tuple[np.ndarray, ...]
    flange: np.ndarray
    ranges: np.ndarray
    style: LinkStyle

    @property
    def dof(self) -> int:
        return len(self.body_pos)


def _rx(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def _standard_dh(rows: list[tuple[float, float, float]]) -> tuple[list, list, np.ndarray]:
    """Bodies from standard DH rows ``(d, a, alpha)``: T_i = Rz(q) Tz(d) Tx(a) Rx(alpha)."""
    pos, rot = [np.zeros(3)], [np.eye(3)]
    for d, a, alpha in rows[:-1]:
        pos.append(np.array([a, 0.0, d]))
        rot.append(_rx(alpha))
    d, a, _ = rows[-1]
    return pos, rot, np.array([a, 0.0, d])


def _modified_dh(rows: list[tuple[float, float, float]], flange: float) -> tuple[list, list, np.ndarray]:
    """Bodies from modified DH rows ``(a_prev, alpha_prev, d)``: T_i = Rx(alpha) Tx(a) Rz(q) Tz(d)."""
    pos, rot = [], []
    for a, alpha, d in rows:
        r = _rx(alpha)
        pos.append(np.array([a, 0.0, 0.0]) + r @ np.array([0.0, 0.0, d]))
        rot.append(r)
    pos[0] = np.zeros(3)  # joint 1 sits on the base plate; d1 becomes the first link's length
    return pos, rot, np.array([0.0, 0.0, flange])


_PI = np.pi
_TABLES = {
    "panda": dict(
        kind="mdh",
        rows=[
            (0.0, 0.0, 0.333),
            (0.0, -_PI / 2, 0.0),
            (0.0, _PI / 2, 0.316),
            (0.0825, _PI / 2, 0.0),
            (-0.0825, -_PI / 2, 0.384),
            (0.0, _PI / 2, 0.0),
            (0.088, _PI / 2, 0.0),
        ],
        flange=0.107,
        style=LinkStyle(radius=0.019, wall=0.003),
        ranges=[
            (-2.8973, 2.8973),
            (-1.7628, 1.7628),
            (-2.8973, 2.8973),
            (-3.0718, -0.0698),
            (-2.8973, 2.8973),
            (-0.0175, 3.7525),
            (-2.8973, 2.8973),
        ],
    ),
    "ur5e": dict(
        kind="dh",
        rows=[
            (0.1625, 0.0, _PI / 2),
            (0.0, -0.425, 0.0),
            (0.0, -0.3922, 0.0),
            (0.1333, 0.0, _PI / 2),
            (0.0997, 0.0, -_PI / 2),
            (0.0996, 0.0, 0.0),
        ],
        ranges=[(-_PI, _PI), (-_PI, 0.0), (-2.8, 2.8), (-_PI, _PI), (-_PI, _PI), (-_PI, _PI)],
    ),
    "xarm7": dict(
        kind="mdh",
        rows=[
            (0.0, 0.0, 0.267),
            (0.0, -_PI / 2, 0.0),
            (0.0, _PI / 2, 0.293),
            (0.0525, _PI / 2, 0.0),
            (0.0775, _PI / 2, 0.3425),
            (0.0, _PI / 2, 0.0),
            (0.076, -_PI / 2, 0.097),
        ],
        flange=0.03,
        style=LinkStyle(radius=0.021, wall=0.003),
        ranges=[
            (-_PI, _PI),
            (-2.059, 2.0944),
            (-_PI, _PI),
            (-0.19198, 3.927),
            (-_PI, _PI),
            (-1.69297, _PI),
            (-_PI, _PI),
        ],
    ),
}


def leader(robot: str) -> Leader:
    """Scaled leader kinematics of ``robot`` (one of ``ROBOTS``)."""
    if robot not in _TABLES:
        raise KeyError(f"unknown robot '{robot}'. Available robots: {', '.join(ROBOTS)}")
    t = _TABLES[robot]
    if t["kind"] == "dh":
        pos, rot, flange = _standard_dh(t["rows"])
        # the base-to-shoulder height d1 is carried by link 1 (joint 1 on the base plate)
    else:
        pos, rot, flange = _modified_dh(t["rows"], t["flange"])
        d1 = t["rows"][0][2]
        pos[1] = pos[1] + np.array([0.0, 0.0, d1])
    return Leader(
        robot=robot,
        body_pos=tuple(SCALE * p for p in pos),
        body_rot=tuple(rot),
        flange=SCALE * flange,
        ranges=np.array(t["ranges"], float),
        style=t.get("style", LinkStyle()),
    )


def servo():
    """The stock servo catalog entry."""
    return load_catalog("servos").get(SERVO_ID)


def pla_density() -> float:
    """PLA density from the materials catalog [kg/m^3]."""
    return float(load_catalog("materials").get(PLA_ID).density)
