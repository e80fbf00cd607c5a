"""The ``03-balance-coins`` scene and its metered environment.

Scene: the tabletop of ``rle_design.scene.tabletop`` (one Panda at (-0.05, 0), table top at
z = 0.75 m), the balance of ``scene`` at ``BALANCE_BASE`` with its beam along world y (the
pan ``balance_pan_left`` at y = -0.15 m, ``balance_pan_right`` at y = +0.15 m), the nine cubes in a
3 x 3 grid (``CUBE_GRID``) and the answer mat (``MAT_CENTRE``, half side ``MAT_HALF``).

Instance (secret): which cube is heavy and by how much; drawn by ``BalanceInstance.draw`` from
``derive_rng(secret, "03-balance-coins", "instance")`` inside the ledger server and the verifier.

Actions: the 12-D layout of ``rle_design.control`` (arm 6, gripper 1, base 3, torso 1, mode 1). The
**mode** entry (index 11) is the balance release: while an action's mode is > 0.5 the beam is free;
an action with mode <= 0.5 locks it at its current angle (no jolt). A **weighing** is one maximal run
of consecutive release actions during which at least one cube rests on a pan (counted once per run,
whatever its length; a run with empty pans is not a weighing). The count survives resets (a reset
restores the scene, not the knowledge gained) and lives in ``MjData.userdata[0]``, so the ledger's
replay reproduces it exactly.

Observation (free), besides the tabletop's: ``balance`` = {``cubes``: 9 x 3 cube centres [m],
``pans``: 2 x 3 tray top centres (left, right) [m], ``mat``: the mat's centre [m], ``released``: bool, ``weighings``: int}. Masses
are never observed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np

from rle_design.control import TabletopEnv
from rle_design.control.layout import MODE
from rle_design.scene.tabletop import TabletopConfig, build_tabletop, finish

from . import scene as bs

TABLE = TabletopConfig()
BALANCE_BASE = (0.40, 0.0)
"""Stand foot on the table (x, y) [m]; the beam runs along world y."""
CUBE_GRID = tuple((x, y) for y in (-0.30, -0.37, -0.44) for x in (0.25, 0.32, 0.39))
"""Initial cube centres (x, y) [m], cube i at ``CUBE_GRID[i]``."""
MAT_CENTRE = (0.30, 0.35)
MAT_HALF = 0.05
PARAMS = bs.BalanceParams()
WEIGHINGS, COUNTED = 0, 1
"""Indices in ``MjData.userdata``: weighings so far; whether the current release run is counted."""
RELEASE_ABOVE = 0.5
"""Mode values above this release the beam."""


@dataclass(frozen=True)
class BalanceInstance:
    """The secret part of a scene.

    Attributes:
        heavy: Index of the heavy cube (0..8).
        heavy_extra: Its extra mass [kg].
        cube_mass: Mass of a light cube [kg].
    """

    heavy: int
    heavy_extra: float
    cube_mass: float = 0.05

    @classmethod
    def draw(cls, rng: np.random.Generator) -> BalanceInstance:
        """Heavy cube uniform over the nine; extra mass uniform in [8, 12] g (tilt 8.5 to 12.7 deg)."""
        heavy = int(rng.integers(bs.N_CUBES))
        return cls(heavy=heavy, heavy_extra=round(float(rng.uniform(0.008, 0.012)), 6))

    @property
    def cubes(self) -> bs.CubeSet:
        return bs.CubeSet(mass=self.cube_mass, heavy_extra=self.heavy_extra, heavy=self.heavy)


def _add_objects(spec: mujoco.MjSpec, instance: BalanceInstance) -> None:
    top = TABLE.top_z
    bs.add_balance(spec, PARAMS, (BALANCE_BASE[0], BALANCE_BASE[1], top), yaw=math.pi / 2)
    half = instance.cubes.size / 2
    positions = np.array([(x, y, top + half) for x, y in CUBE_GRID])
    bs.add_cubes(spec, instance.cubes, positions)
    bs.add_mat(spec, (MAT_CENTRE[0], MAT_CENTRE[1], top + 0.0005), MAT_HALF)
    spec.nuserdata = 2


def scene_xml(instance: BalanceInstance) -> str:
    """MJCF of the full scene (robot, cameras, balance, cubes, mat) with keyframe ``initial``."""
    spec = build_tabletop(TABLE)
    _add_objects(spec, instance)
    finish(spec, TABLE)
    return spec.to_xml()


def robotless_spec(instance: BalanceInstance) -> mujoco.MjSpec:
    """The table, balance, cubes and mat without the robot (the verifier's settling scene)."""
    spec = mujoco.MjSpec()
    spec.option.timestep = TABLE.timestep
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
    hx, hy = TABLE.half_size
    table = spec.worldbody.add_geom()
    table.name = "table"
    table.type = mujoco.mjtGeom.mjGEOM_BOX
    table.size = np.array([hx, hy, TABLE.thickness / 2])
    table.pos = np.array([TABLE.center_x, 0.0, TABLE.top_z - TABLE.thickness / 2])
    table.friction = np.array([TABLE.friction, 0.005, 0.0001])
    _add_objects(spec, instance)
    return spec


def cubes_on_pans(model: mujoco.MjModel, data: mujoco.MjData) -> list[list[int]]:
    """Indices of the cubes resting on the (left, right) pan: centre over the tray, within 4 cube heights."""
    out: list[list[int]] = []
    size = bs.CubeSet().size
    for tray in bs.TRAYS:
        g = model.geom(tray).id
        centre, rot = data.geom_xpos[g], data.geom_xmat[g].reshape(3, 3)
        top = model.geom_size[g, 2]
        on = []
        for i in range(bs.N_CUBES):
            local = rot.T @ (data.xpos[model.body(bs.cube_name(i)).id] - centre)
            if (
                abs(local[0]) <= PARAMS.tray_half[0]
                and abs(local[1]) <= PARAMS.tray_half[1]
                and top < local[2] < top + 4 * size
            ):
                on.append(i)
        out.append(on)
    return out


def balance_observation(model: mujoco.MjModel, data: mujoco.MjData) -> dict[str, Any]:
    """The ``balance`` observation (module docstring)."""
    pans = []
    for tray in bs.TRAYS:
        g = model.geom(tray).id
        pans.append(data.geom_xpos[g] + np.array([0.0, 0.0, model.geom_size[g, 2]]))
    return {
        "cubes": np.array([data.xpos[model.body(bs.cube_name(i)).id] for i in range(bs.N_CUBES)]),
        "pans": np.array(pans),
        "mat": data.geom_xpos[model.geom(bs.MAT).id].copy(),
        "released": not bs.is_locked(model, data),
        "weighings": int(data.userdata[WEIGHINGS]),
    }


@dataclass(frozen=True)
class BalanceEnv(TabletopEnv):
    """The tabletop environment with the balance release on the mode entry (module docstring)."""

    observers: tuple = (("balance", balance_observation),)

    def reset(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        weighings = float(data.userdata[WEIGHINGS])
        model.eq_data[model.equality(bs.LOCK).id, 0] = 0.0
        super().reset(model, data)
        data.userdata[WEIGHINGS] = weighings
        data.userdata[COUNTED] = 0.0

    def step(self, model: mujoco.MjModel, data: mujoco.MjData, ctrl: np.ndarray) -> None:
        mode = float(np.nan_to_num(ctrl[MODE]))
        released = mode > RELEASE_ABOVE
        if released and bs.is_locked(model, data):
            bs.release(model, data)
            data.userdata[COUNTED] = 0.0
        elif not released and not bs.is_locked(model, data):
            bs.lock(model, data)
            mujoco.mj_forward(model, data)
        super().step(model, data, ctrl)
        if released and not data.userdata[COUNTED] and any(cubes_on_pans(model, data)):
            data.userdata[WEIGHINGS] += 1.0
            data.userdata[COUNTED] = 1.0


def make_env(
    instance: BalanceInstance, *, privileged: bool = False, image_size: tuple[int, int] | None = (120, 160)
) -> BalanceEnv:
    """The metered environment of ``instance`` (``privileged`` adds free-body poses: reference and tests only)."""
    return BalanceEnv(xml=scene_xml(instance), privileged=privileged, image_size=image_size)
