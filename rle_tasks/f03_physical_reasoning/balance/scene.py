"""The two-pan balance, nine cubes and the answer mat of ``03-balance-coins``, built with ``MjSpec``.

Mechanism (all lengths in the balance frame, x along the beam, z up, origin at the pivot):

- a fixed stand holds the beam on a hinge about y at the pivot;
- the beam is a bar (mass ``bar_mass``, centred on the pivot) and a bob (mass ``bob_mass``, centred at
  depth ``bob_depth`` below it); its centre of mass lies ``d = bob_mass bob_depth / M_beam`` below the
  pivot, with ``M_beam = bar_mass + bob_mass``;
- each pan hangs from a hinge about y at ``(+-arm_length, 0, 0)``, on the beam's axis line, so a load
  on a pan acts on the beam as a vertical force through that point whatever the tilt; the tray sits
  ``tray_offset`` along +y from below its hang point (open above for a gripper), an offset along the
  hinge axes that adds no moment about them;
- moment balance about the pivot at tilt theta: ``dm g L cos(theta) = M_beam g d sin(theta)``, so
  ``tan(theta) = dm L_arm / (M_beam d)`` (``dm`` = left load minus right load; positive theta lowers
  the left pan (at -x), i.e. the beam hinge angle is q = -theta);
- a lock: an equality constraint holding the beam hinge at an angle (``eq_active`` toggled by the
  environment); released, the beam is free within +-``tilt_limit``.

Cubes are free bodies of one size and colour; their masses are the instance's secret. The mat is a
visual-only patch on the table.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

BEAM = "balance_beam"
BEAM_HINGE = "balance_hinge"
LOCK = "balance_lock"
PANS = ("balance_pan_left", "balance_pan_right")
TRAYS = ("balance_tray_left", "balance_tray_right")
MAT = "answer_mat"
N_CUBES = 9


def cube_name(i: int) -> str:
    """Body (and geom) name of cube ``i`` (0..8)."""
    return f"cube_{i}"


@dataclass(frozen=True)
class BalanceParams:
    """Geometry and masses of the balance (SI units)."""

    arm_length: float = 0.15
    """L_arm: pivot to pan hang point [m]."""
    bar_mass: float = 0.2
    """Mass of the beam's bar, centred on the pivot [kg]."""
    bob_mass: float = 0.1
    """Mass of the bob below the pivot [kg]."""
    bob_depth: float = 0.08
    """Depth of the bob's centre below the pivot [m]."""
    hang_depth: float = 0.08
    """Depth of a tray's top below its hang point [m]."""
    tray_half: tuple[float, float] = (0.03, 0.085)
    """Half extents of a pan tray along the beam and along the hinge axis [m]; loads go in a row along
    the hinge axis, where their offsets tilt no pan."""
    tray_offset: float = 0.1
    """Offset of a tray's centre from its hang point along the hinge axis (balance y) [m]: leaves the
    space above the tray free of the beam; along the hinge axis it changes no moment about it."""
    pan_mass: float = 0.15
    """Mass of one pan (tray) [kg]."""
    pivot_height: float = 0.16
    """Height of the pivot above the table top [m]."""
    tilt_limit: float = 0.3
    """Beam hinge range +- [rad]."""
    beam_damping: float = 0.02
    """Beam hinge damping [N m s/rad] (settles a three-cube weighing to 1 % within 4 s)."""
    pan_damping: float = 0.01
    """Pan hinge damping [N m s/rad]."""
    # pan masses act at the hang points like equal loads: they leave tan(theta) unchanged

    @property
    def beam_mass(self) -> float:
        """M_beam [kg]."""
        return self.bar_mass + self.bob_mass

    @property
    def com_depth(self) -> float:
        """d: depth of the beam's centre of mass below the pivot [m]."""
        return self.bob_mass * self.bob_depth / self.beam_mass

    def tilt(self, dm: float) -> float:
        """Equilibrium tilt [rad] for a load difference ``dm`` [kg] (left minus right)."""
        return math.atan(dm * self.arm_length / (self.beam_mass * self.com_depth))


@dataclass(frozen=True)
class CubeSet:
    """The nine cubes.

    Attributes:
        size: Edge length [m].
        mass: Mass of a light cube [kg].
        heavy_extra: Extra mass of the heavy cube [kg].
        heavy: Index of the heavy cube (secret).
    """

    size: float = 0.03
    mass: float = 0.05
    heavy_extra: float = 0.01
    heavy: int = 0

    def masses(self) -> tuple[float, ...]:
        return tuple(self.mass + (self.heavy_extra if i == self.heavy else 0.0) for i in range(N_CUBES))


def _box(
    body: mujoco.MjsBody,
    name: str,
    half: tuple[float, ...],
    pos: tuple[float, ...],
    mass: float,
    rgba: tuple[float, ...],
    collide: bool = True,
) -> mujoco.MjsGeom:
    geom = body.add_geom()
    geom.name = name
    geom.type = mujoco.mjtGeom.mjGEOM_BOX
    geom.size = np.asarray(half, dtype=float)
    geom.pos = np.asarray(pos, dtype=float)
    geom.rgba = np.asarray(rgba, dtype=float)
    geom.mass = mass
    if not collide:
        geom.contype = 0
        geom.conaffinity = 0
    return geom


def add_balance(
    spec: mujoco.MjSpec, params: BalanceParams, base: tuple[float, float, float], yaw: float = 0.0
) -> None:
    """Add stand, beam, pans and the lock to ``spec``.

    Args:
        spec: The scene.
        params: The balance.
        base: The stand's foot on the table [m].
        yaw: Heading of the balance frame about world z [rad] (0: beam along world x).
    """
    p = params
    stand = spec.worldbody.add_body()
    stand.name = "balance_stand"
    stand.pos = np.asarray(base, dtype=float)
    stand.quat = np.array([math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)])
    grey = (0.45, 0.45, 0.5, 1.0)
    _box(stand, "balance_foot", (0.05, 0.03, 0.005), (0, 0, 0.005), 0.0, grey)
    _box(
        stand, "balance_post", (0.008, 0.008, p.pivot_height / 2), (0, -0.025, p.pivot_height / 2), 0.0, grey
    )
    beam = stand.add_body()
    beam.name = BEAM
    beam.pos = np.array([0.0, 0.0, p.pivot_height])
    hinge = beam.add_joint()
    hinge.name = BEAM_HINGE
    hinge.type = mujoco.mjtJoint.mjJNT_HINGE
    hinge.axis = np.array([0.0, 1.0, 0.0])
    limit = math.degrees(p.tilt_limit) if spec.compiler.degree else p.tilt_limit
    hinge.range = np.array([-limit, limit])
    hinge.limited = mujoco.mjtLimited.mjLIMITED_TRUE
    hinge.damping = np.array([p.beam_damping, 0.0, 0.0])
    hinge.armature = 1e-4
    brass = (0.75, 0.6, 0.25, 1.0)
    _box(beam, "balance_bar", (p.arm_length + 0.01, 0.006, 0.004), (0, 0, 0), p.bar_mass, brass)
    _box(beam, "balance_bob", (0.006, 0.006, 0.01), (0, 0, -p.bob_depth), p.bob_mass, brass, collide=False)
    _box(
        beam, "balance_pointer", (0.002, 0.002, p.bob_depth / 2), (0, 0, -p.bob_depth / 2), 0.0, brass, False
    )
    for side, (pan_name, tray_name) in zip((1.0, -1.0), zip(PANS, TRAYS)):
        pan = beam.add_body()
        pan.name = pan_name
        pan.pos = np.array([-side * p.arm_length, 0.0, 0.0])
        joint = pan.add_joint()
        joint.name = f"{pan_name}_hinge"
        joint.type = mujoco.mjtJoint.mjJNT_HINGE
        joint.axis = np.array([0.0, 1.0, 0.0])
        joint.damping = np.array([p.pan_damping, 0.0, 0.0])
        joint.armature = 1e-4
        off, depth = p.tray_offset, p.hang_depth
        _box(pan, f"{pan_name}_rod", (0.002, 0.002, depth / 2), (0, 0, -depth / 2), 0.0, grey, False)
        _box(pan, f"{pan_name}_arm", (0.002, off / 2, 0.002), (0, off / 2, -depth), 0.0, grey, False)
        _box(pan, tray_name, (*p.tray_half, 0.003), (0, off, -depth - 0.003), p.pan_mass, brass)
    lock = spec.add_equality()
    lock.name = LOCK
    lock.type = mujoco.mjtEq.mjEQ_JOINT
    lock.name1 = BEAM_HINGE
    lock.data = np.zeros(12)
    lock.solref = np.array([0.005, 1.0])
    lock.active = True


def add_cubes(spec: mujoco.MjSpec, cubes: CubeSet, positions: np.ndarray) -> None:
    """Add the nine free cubes at ``positions`` (9 x 3, centres [m]); identical apart from mass."""
    half = cubes.size / 2
    for i, (mass, pos) in enumerate(zip(cubes.masses(), positions)):
        body = spec.worldbody.add_body()
        body.name = cube_name(i)
        body.pos = np.asarray(pos, dtype=float)
        free = body.add_freejoint()
        free.name = f"{cube_name(i)}_free"
        geom = _box(body, cube_name(i), (half, half, half), (0, 0, 0), mass, (0.2, 0.45, 0.8, 1.0))
        geom.friction = np.array([1.0, 0.01, 0.001])


def add_mat(spec: mujoco.MjSpec, centre: tuple[float, float, float], half: float) -> None:
    """Add the answer mat: a visual-only green square of half side ``half`` on the table at ``centre``."""
    _box(spec.worldbody, MAT, (half, half, 0.0005), centre, 0.0, (0.2, 0.7, 0.3, 1.0), collide=False)


def release(model: mujoco.MjModel, data: mujoco.MjData) -> None:
    """Free the beam."""
    data.eq_active[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_EQUALITY, LOCK)] = 0


def lock(model: mujoco.MjModel, data: mujoco.MjData) -> None:
    """Hold the beam at its current angle (no jolt)."""
    eq = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_EQUALITY, LOCK)
    qadr = model.jnt_qposadr[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, BEAM_HINGE)]
    model.eq_data[eq, 0] = data.qpos[qadr]
    data.eq_active[eq] = 1


def is_locked(model: mujoco.MjModel, data: mujoco.MjData) -> bool:
    return bool(data.eq_active[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_EQUALITY, LOCK)])


def beam_angle(model: mujoco.MjModel, data: mujoco.MjData) -> float:
    """Beam hinge angle q [rad]; positive q raises the left pan (at -x), so q = -theta."""
    return float(
        data.qpos[model.jnt_qposadr[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, BEAM_HINGE)]]
    )
