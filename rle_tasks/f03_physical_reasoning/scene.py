"""The family's tabletop scene: pieces on the table, the metered environment, the robot-free settle.

Every task of the family describes its instance as ``Piece``s (free bodies with a box or convex-mesh
shape) placed on the tabletop of ``rle_design.scene.tabletop``. ``make_env(pieces)`` builds the
metered development environment (the Panda, 20 Hz actions, ``rle_design.control.TabletopEnv``);
``settle(pieces, poses)`` rebuilds the same table and pieces **without the robot** at the recorded
poses (velocities zero) and lets them settle for ``SETTLE_S`` seconds: what stands then is what is
scored.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import mujoco
import numpy as np

from rle_design.control import TabletopEnv
from rle_design.scene.tabletop import TabletopConfig, add_free_box, build_tabletop, finish

__all__ = [
    "CONFIG",
    "N_SUBSTEPS",
    "SETTLE_S",
    "Piece",
    "SceneEdit",
    "make_env",
    "piece_poses",
    "scene_spec",
    "settle",
]

CONFIG = TabletopConfig()
"""The family's table: top at 0.75 m, edge at x = 0.45 m (normal +x), one Panda at (-0.05, 0)."""
N_SUBSTEPS = 25
"""Physics steps per action: 2 ms x 25 = 50 ms (20 Hz)."""
SETTLE_S = 3.0
"""Robot-free settling time before measuring [s]: a block tipping from rest about an edge falls
off a 0.75 m table within about 1 s (free fall 0.39 s plus the tipping motion), so 3 s leaves
everything that is going to fall on the floor."""
REST_SPEED = 0.01
"""A piece moving faster than this after settling is reported as still moving [m/s]."""


@dataclass(frozen=True)
class Piece:
    """One free piece.

    Attributes:
        name: Body and geom name.
        half_size: Box half extents [m] (for a wedge: the bounding box's half extents).
        pos: Spawn position [m].
        yaw: Spawn heading about z [rad].
        mass: Mass [kg].
        shape: ``"box"`` or ``"wedge"`` (a triangular prism, ridge along x: it cannot support others).
        rgba: Colour.
    """

    name: str
    half_size: tuple[float, float, float]
    pos: tuple[float, float, float]
    yaw: float = 0.0
    mass: float = 0.1
    shape: str = "box"
    rgba: tuple[float, float, float, float] = (0.8, 0.3, 0.2, 1.0)

    @property
    def quat(self) -> tuple[float, float, float, float]:
        return (float(np.cos(self.yaw / 2)), 0.0, 0.0, float(np.sin(self.yaw / 2)))


def _add_piece(spec: mujoco.MjSpec, piece: Piece) -> None:
    if piece.shape == "box":
        add_free_box(spec, piece.name, piece.half_size, piece.pos, quat=piece.quat, mass=piece.mass,
                     rgba=piece.rgba)  # fmt: skip
        return
    hx, hy, hz = piece.half_size
    verts = [(-hx, -hy, -hz), (hx, -hy, -hz), (-hx, hy, -hz), (hx, hy, -hz), (-hx, 0, hz), (hx, 0, hz)]
    spec.add_mesh(name=piece.name + "_mesh", uservert=np.ravel(verts).tolist())
    body = spec.worldbody.add_body(name=piece.name, pos=list(piece.pos), quat=list(piece.quat))
    body.add_freejoint(name=piece.name)
    body.add_geom(name=piece.name, type=mujoco.mjtGeom.mjGEOM_MESH, meshname=piece.name + "_mesh",
                  mass=piece.mass, rgba=list(piece.rgba), condim=4)  # fmt: skip


SceneEdit = Callable[[mujoco.MjSpec], None]
"""Adds task-specific elements (a balance, sealed boxes, ...) to the scene spec before it is finished;
a module-level function, applied alike to the metered scene and the robot-free settle scene."""


def scene_spec(
    pieces: tuple[Piece, ...], robot: bool = True, extras: tuple[SceneEdit, ...] = ()
) -> mujoco.MjSpec:
    """Table, (robot), pieces, ``extras``, keyframe ``initial``."""
    config = CONFIG if robot else TabletopConfig(arms=())
    spec = build_tabletop(config)
    for piece in pieces:
        _add_piece(spec, piece)
    for edit in extras:
        edit(spec)
    return finish(spec, config)


def make_env(
    pieces: tuple[Piece, ...],
    *,
    privileged: bool = False,
    images: bool = True,
    extras: tuple[SceneEdit, ...] = (),
) -> TabletopEnv:
    """The metered environment of an instance (agents: ``privileged=False``)."""
    xml = scene_spec(pieces, extras=extras).to_xml()
    return TabletopEnv(
        xml=xml, n_substeps=N_SUBSTEPS, privileged=privileged, image_size=(120, 160) if images else None
    )


def settle(
    pieces: tuple[Piece, ...],
    poses: dict[str, np.ndarray],
    seconds: float = SETTLE_S,
    extras: tuple[SceneEdit, ...] = (),
) -> tuple[mujoco.MjModel, mujoco.MjData, float]:
    """Robot-free scene with each piece at ``poses[name]`` (x, y, z, qw, qx, qy, qz), settled.

    Other joints (those of ``extras``) start from their defaults.

    Returns:
        (model, data, largest piece speed at the end [m/s]).
    """
    model = scene_spec(pieces, robot=False, extras=extras).compile()
    data = mujoco.MjData(model)
    mujoco.mj_resetData(model, data)
    for piece in pieces:
        adr = model.jnt_qposadr[model.joint(piece.name).id]
        data.qpos[adr : adr + 7] = poses[piece.name]
    mujoco.mj_forward(model, data)
    mujoco.mj_step(model, data, int(round(seconds / model.opt.timestep)))
    speed = max(
        (float(np.linalg.norm(data.qvel[model.jnt_dofadr[model.joint(p.name).id] :][:3])) for p in pieces),
        default=0.0,
    )
    return model, data, speed


def piece_poses(
    model: mujoco.MjModel, data: mujoco.MjData, pieces: tuple[Piece, ...]
) -> dict[str, np.ndarray]:
    """Name -> (x, y, z, qw, qx, qy, qz) of each piece's free joint."""
    out = {}
    for piece in pieces:
        adr = model.jnt_qposadr[model.joint(piece.name).id]
        out[piece.name] = data.qpos[adr : adr + 7].copy()
    return out
