"""RoboCasa's success predicates over a compiled kitchen, written out one by one.

- A door's (or drawer's) normalised state is ``(q - low) / (high - low)`` of its joint; a fixture is
  **open** when every one of its door joints is at least ``OPEN_AT`` = 0.90, **closed** when every one
  is at most ``CLOSED_AT`` = 0.005 (RoboCasa ``Fixture.is_open`` / ``is_closed``).
- A stove burner is **on** when its knob's angle wrapped to [0, 2 pi) lies in [``KNOB_ON``,
  2 pi - ``KNOB_ON``], ``KNOB_ON`` = 0.35 rad (RoboCasa ``Stove.get_knobs_state``).
- An object is **inside** a fixture when all eight corners of its bounding box (the box around its
  geoms in its body frame, placed at its current pose) lie within the fixture's interior box grown
  by ``INSIDE_TOL`` = 0.05 m (RoboCasa ``OU.obj_inside_of``).
- The gripper is **far** from an object when every finger is more than ``GRIPPER_FAR`` = 0.25 m from
  the object's centre (RoboCasa ``OU.gripper_obj_far``).
- An object is **in a receptacle** (plate, bowl) when the two touch and the object's centre lies
  within 0.7 of the receptacle's radius of its centre in the horizontal plane (RoboCasa
  ``OU.check_obj_in_receptacle``).
- Two bodies **touch** when a contact joins a geom of each.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from rle_tasks.envs.kitchen.fixture import Fixture, Interior
from rle_tasks.envs.kitchen.objects import extent

__all__ = [
    "CLOSED_AT",
    "GRIPPER_FAR",
    "INSIDE_TOL",
    "KNOB_ON",
    "OPEN_AT",
    "bodies_touch",
    "corners",
    "gripper_far",
    "in_receptacle",
    "inside",
    "is_closed",
    "is_open",
    "joint_fraction",
    "knob_on",
    "on_site",
    "wrapped",
]

OPEN_AT = 0.90
CLOSED_AT = 0.005
KNOB_ON = 0.35
INSIDE_TOL = 0.05
GRIPPER_FAR = 0.25
RECEPTACLE_RADIUS = 0.7


def joint_fraction(model: mujoco.MjModel, data: mujoco.MjData, joint: str) -> float:
    """Normalised state of a limited joint: 0 at its lower limit, 1 at its upper one."""
    j = model.joint(joint)
    low, high = model.jnt_range[j.id]
    return float((data.qpos[model.jnt_qposadr[j.id]] - low) / (high - low))


def is_open(model: mujoco.MjModel, data: mujoco.MjData, fixture: Fixture) -> bool:
    """Every door (or drawer) joint of ``fixture`` is at least ``OPEN_AT`` open."""
    return bool(fixture.joints) and all(joint_fraction(model, data, j) >= OPEN_AT for j in fixture.joints)


def is_closed(model: mujoco.MjModel, data: mujoco.MjData, fixture: Fixture) -> bool:
    """Every door (or drawer) joint of ``fixture`` is at most ``CLOSED_AT`` open."""
    return bool(fixture.joints) and all(joint_fraction(model, data, j) <= CLOSED_AT for j in fixture.joints)


def wrapped(angle: float) -> float:
    """``angle`` wrapped to [0, 2 pi) [rad]."""
    return float(angle % (2 * math.pi))


def knob_on(model: mujoco.MjModel, data: mujoco.MjData, knob_joint: str) -> bool:
    """The knob's wrapped angle lies in [KNOB_ON, 2 pi - KNOB_ON]."""
    a = wrapped(data.qpos[model.jnt_qposadr[model.joint(knob_joint).id]])
    return KNOB_ON <= a <= 2 * math.pi - KNOB_ON


def corners(model: mujoco.MjModel, data: mujoco.MjData, obj: str, category: str) -> np.ndarray:
    """(8, 3) world corners of the object's bounding box [m]."""
    center, half = extent(category)
    b = model.body(obj).id
    signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float)
    local = np.asarray(center) + signs * np.asarray(half)
    return data.xpos[b] + local @ data.xmat[b].reshape(3, 3).T


def inside(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    obj: str,
    category: str,
    interior: Interior,
    tol: float = INSIDE_TOL,
) -> bool:
    """All eight corners of the object's box lie inside ``interior`` grown by ``tol`` [m]."""
    b = model.body(interior.body).id
    rot = data.xmat[b].reshape(3, 3)
    local = (corners(model, data, obj, category) - data.xpos[b]) @ rot - np.asarray(interior.center)
    return bool(np.all(np.abs(local) <= np.asarray(interior.half) + tol))


def gripper_far(
    model: mujoco.MjModel, data: mujoco.MjData, obj: str, fingers: tuple[str, str], th: float = GRIPPER_FAR
) -> bool:
    """Every finger body is farther than ``th`` [m] from the object's centre."""
    p = data.xpos[model.body(obj).id]
    return all(float(np.linalg.norm(data.xpos[model.body(f).id] - p)) > th for f in fingers)


def _body_geoms(model: mujoco.MjModel, body: int) -> set[int]:
    start, n = model.body_geomadr[body], model.body_geomnum[body]
    return set(range(start, start + n)) if start >= 0 else set()


def bodies_touch(model: mujoco.MjModel, data: mujoco.MjData, a: str, b: str | set[int]) -> bool:
    """A contact joins a geom of body ``a`` and a geom of body ``b`` (or one of the geom ids ``b``)."""
    ga = _body_geoms(model, model.body(a).id)
    gb = b if isinstance(b, set) else _body_geoms(model, model.body(b).id)
    for c in data.contact[: data.ncon]:
        g1, g2 = int(c.geom1), int(c.geom2)
        if (g1 in ga and g2 in gb) or (g2 in ga and g1 in gb):
            return True
    return False


def in_receptacle(
    model: mujoco.MjModel, data: mujoco.MjData, obj: str, receptacle: str, category: str
) -> bool:
    """``obj`` touches ``receptacle`` and lies within 0.7 of its radius of its centre (horizontally)."""
    if not bodies_touch(model, data, obj, receptacle):
        return False
    center, half = extent(category)
    rb = model.body(receptacle).id
    c = data.xpos[rb] + data.xmat[rb].reshape(3, 3) @ np.asarray(center)
    d = float(np.linalg.norm(data.xpos[model.body(obj).id][:2] - c[:2]))
    return d < RECEPTACLE_RADIUS * max(half[0], half[1])


def on_site(
    model: mujoco.MjModel, data: mujoco.MjData, obj: str, geom: str, site: str, radius: float
) -> bool:
    """``obj`` touches ``geom`` and its centre lies within ``radius`` [m] of ``site`` horizontally (an
    object standing on a burner)."""
    if not bodies_touch(model, data, obj, {model.geom(geom).id}):
        return False
    d = data.xpos[model.body(obj).id][:2] - data.site_xpos[model.site(site).id][:2]
    return float(np.linalg.norm(d)) <= radius
