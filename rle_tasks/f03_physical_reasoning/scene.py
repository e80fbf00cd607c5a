"""The family's tabletop scene: pieces on the table, the metered environment, the robot-free settle.

Every task of the family describes its instance as ``Piece``s (free bodies with a box or convex-mesh
shape) placed on the tabletop of ``rle_design.scene.tabletop``. ``make_env(pieces)`` builds the
metered development environment (the Panda, 20 Hz actions, ``rle_design.control.TabletopEnv``);
``settle(pieces, poses, velocities=...)`` rebuilds the same table and pieces **without the robot** at
the recorded poses, with the recorded velocities (zero when none are given), and simulates
``SETTLE_S`` seconds. A piece is **at rest** when over the last ``REST_WINDOW_S`` it stayed within
``REST_DISP_M`` (its centre) and ``REST_ANGLE`` of its pose at the start of that window (``at_rest``,
sampled every ``REST_SAMPLE_S``): a displacement over a window, not an instantaneous speed, because
the contact solver leaves resting stacks with a speed jitter of 0.005-0.02 m/s that goes nowhere
(the stack of the cantilever reference: 0.26 mm in 30 s). What stands and rests then is scored.

Tipping closed form (the basis of ``SETTLE_S`` and ``REST_WINDOW_S``): a rigid block of length L and
height h lying on a support edge with its centre of mass delta beyond the edge turns about the edge
as theta'' = k^2 (theta + 2 delta / h), k^2 = g (h/2) / (I_edge / m), I_edge / m = (L^2 + h^2)/12 +
delta^2 + (h/2)^2; from rest theta(t) = (2 delta / h)(cosh(k t) - 1), so it reaches theta after
t = acosh(1 + theta h / (2 delta)) / k. The slowest piece of the family is the longest cantilever
block (L = 0.18 m, h = 0.03 m: k = 7.0 /s; tower pieces k >= 8.9 /s, a whole 0.35 m tower about its
base k = sqrt(1.5 g / H) = 6.5 /s).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import mujoco
import numpy as np

from rle_design.control import TabletopEnv
from rle_design.scene.tabletop import TabletopConfig, add_free_box, build_tabletop, finish

__all__ = [
    "CONFIG",
    "N_SUBSTEPS",
    "REST_ANGLE",
    "REST_DISP_M",
    "REST_SAMPLE_S",
    "REST_WINDOW_S",
    "SETTLE_S",
    "Piece",
    "SceneEdit",
    "Settled",
    "at_rest",
    "make_env",
    "piece_poses",
    "piece_velocities",
    "rest_motion",
    "scene_spec",
    "settle",
]

CONFIG = TabletopConfig()
"""The family's table: top at 0.75 m, edge at x = 0.45 m (normal +x), one Panda at (-0.05, 0)."""
N_SUBSTEPS = 25
"""Physics steps per action: 2 ms x 25 = 50 ms (20 Hz)."""
SETTLE_S = 20.0
"""Robot-free settling time [s]. Closed form (module docstring): the longest cantilever block with its
centre of mass 0.5 mm past its support edge reaches 30 deg after acosh(1 + (pi/6) 0.03 / 0.001) / 7.0
= 0.50 s (simulated 0.49 s) and is on the floor (centre below 0.1 m) after 0.94 s (simulated; free
fall from the 0.75 m top alone takes 0.39 s); the time grows only as ln(1/delta) (delta = 0.05 mm:
0.82 s to 30 deg). 20 s
is 20 times that, a margin for what the rigid closed form does not have: stacks within a few tenths
of a millimetre of their tipping point creep under the soft contacts (micrometres per second) and
fall late. Shifting the shipped cantilever reference (or its top block) outward in 0.02 mm steps
across its tipping point, 13 of 17 falls came within 3 s (the former horizon), 15 within 20 s, and
two, from shifts within 0.2 mm below the sharp threshold, after 24.7 s and 43.7 s. Cost: 6.4 to 6.9
times the former 3 s settle (tower 1.29 s, cantilever 0.36 s on the 2-core development machine)."""
REST_WINDOW_S = 2.0
"""A piece is at rest when it stayed put over the last ``REST_WINDOW_S`` of the settle [s]. A block
that has begun to tip by delta (closed form) moves its centre about delta (cosh(k t) - 1): with k >=
6.5 /s, over 2 s that exceeds 1 mm for any delta >= 5 nm, so no piece that is tipping passes."""
REST_DISP_M = 1e-3
"""Largest displacement of a resting piece's centre over the rest window [m]: 2.6 times the largest
2 s displacement (0.38 mm) of any block of the standing cantilever reference stacks, shifted outward
by 0 to 5.2 mm and simulated for 30 s (jitter and creep included); 0.6 % of the smallest cantilever
optimum (1.168 x 0.14 m), 0.3 % of a tower H*."""
REST_ANGLE = math.radians(1.0)
"""Largest rotation of a resting piece over the rest window [rad] (1 deg): at the end of the longest
block (0.09 m from its centre) 1 deg moves 1.6 mm, the scale of ``REST_DISP_M``; five times the
largest 2 s rotation (0.19 deg) of a block in the same standing stacks."""
REST_SAMPLE_S = 0.1
"""Sampling interval of the poses within the rest window [s] (21 samples, start and end included)."""


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


def rest_motion(
    pos_start: np.ndarray, quat_start: np.ndarray, pos_end: np.ndarray, quat_end: np.ndarray
) -> tuple[float, float]:
    """Displacement of a piece's centre [m] and its rotation angle [rad] from one pose to another
    (quaternions w, x, y, z; either sign)."""
    disp = float(np.linalg.norm(np.asarray(pos_end, float) - np.asarray(pos_start, float)))
    qa, qb = np.asarray(quat_start, float), np.asarray(quat_end, float)
    dot = abs(float(qa @ qb)) / (float(np.linalg.norm(qa)) * float(np.linalg.norm(qb)))
    return disp, 2.0 * math.acos(min(1.0, dot))


def at_rest(pos_start: np.ndarray, quat_start: np.ndarray, pos_end: np.ndarray, quat_end: np.ndarray) -> bool:
    """The rest rule on two poses: the centre moved less than ``REST_DISP_M`` and the piece turned
    less than ``REST_ANGLE`` (``rest_motion``)."""
    disp, angle = rest_motion(pos_start, quat_start, pos_end, quat_end)
    return disp < REST_DISP_M and angle < REST_ANGLE


@dataclass(frozen=True)
class Settled:
    """The robot-free scene after ``settle``.

    Attributes:
        model: The robot-free model.
        data: Its state at the end of the settle.
        poses: Name -> final pose (x, y, z, qw, qx, qy, qz) of each piece.
        at_rest: Name -> the piece stayed within ``REST_DISP_M`` and ``REST_ANGLE`` of its pose at the
            start of the rest window at every sample of it.
        window_disp_m: Name -> largest displacement of the centre from the window-start pose [m].
        window_angle_rad: Name -> largest rotation from the window-start pose [rad].
    """

    model: mujoco.MjModel
    data: mujoco.MjData
    poses: dict[str, np.ndarray]
    at_rest: dict[str, bool]
    window_disp_m: dict[str, float]
    window_angle_rad: dict[str, float]

    @property
    def max_disp_m(self) -> float:
        """Largest ``window_disp_m`` over the pieces [m] (0 without pieces)."""
        return max(self.window_disp_m.values(), default=0.0)

    @property
    def max_speed_mps(self) -> float:
        """Largest linear speed of a piece at the end [m/s] (information only: the jitter)."""
        speeds = (
            float(np.linalg.norm(self.data.qvel[self.model.jnt_dofadr[self.model.joint(n).id] :][:3]))
            for n in self.poses
        )
        return max(speeds, default=0.0)


def settle(
    pieces: tuple[Piece, ...],
    poses: Mapping[str, np.ndarray],
    seconds: float = SETTLE_S,
    extras: tuple[SceneEdit, ...] = (),
    velocities: Mapping[str, np.ndarray] | None = None,
) -> Settled:
    """Robot-free scene with each piece at ``poses[name]`` (x, y, z, qw, qx, qy, qz), simulated for
    ``seconds`` and judged at rest over the last ``REST_WINDOW_S`` (module docstring).

    Args:
        pieces: The pieces.
        poses: Name -> pose of every piece.
        seconds: Simulated time [s], at least ``REST_WINDOW_S``.
        extras: Scene edits (``SceneEdit``); their joints start from their defaults.
        velocities: Name -> the 6 ``qvel`` entries of the piece's free joint (``piece_velocities`` of
            the replayed state) for every piece; None: all pieces start at rest.

    Raises:
        ValueError: ``seconds`` shorter than the rest window.
    """
    if seconds < REST_WINDOW_S:
        raise ValueError(f"settle: {seconds} s is shorter than the rest window {REST_WINDOW_S} s")
    model = scene_spec(pieces, robot=False, extras=extras).compile()
    data = mujoco.MjData(model)
    mujoco.mj_resetData(model, data)
    qpos = [int(model.jnt_qposadr[model.joint(p.name).id]) for p in pieces]
    dofs = [int(model.jnt_dofadr[model.joint(p.name).id]) for p in pieces]
    for piece, adr, dof in zip(pieces, qpos, dofs):
        data.qpos[adr : adr + 7] = poses[piece.name]
        if velocities is not None:
            data.qvel[dof : dof + 6] = velocities[piece.name]
    mujoco.mj_forward(model, data)
    dt = model.opt.timestep
    n_total = int(round(seconds / dt))
    n_sample = max(1, int(round(REST_SAMPLE_S / dt)))
    n_window = min(n_total, n_sample * max(1, int(round(REST_WINDOW_S / (n_sample * dt)))))
    mujoco.mj_step(model, data, n_total - n_window)
    start = [data.qpos[adr : adr + 7].copy() for adr in qpos]
    disp = np.zeros(len(pieces))
    angle = np.zeros(len(pieces))
    for _ in range(n_window // n_sample):
        mujoco.mj_step(model, data, n_sample)
        for i, adr in enumerate(qpos):
            d, a = rest_motion(
                start[i][:3], start[i][3:], data.qpos[adr : adr + 3], data.qpos[adr + 3 : adr + 7]
            )
            disp[i], angle[i] = max(disp[i], d), max(angle[i], a)
    names = [p.name for p in pieces]
    return Settled(
        model,
        data,
        {n: data.qpos[adr : adr + 7].copy() for n, adr in zip(names, qpos)},
        {n: bool(disp[i] < REST_DISP_M and angle[i] < REST_ANGLE) for i, n in enumerate(names)},
        {n: float(disp[i]) for i, n in enumerate(names)},
        {n: float(angle[i]) for i, n in enumerate(names)},
    )


def piece_poses(
    model: mujoco.MjModel, data: mujoco.MjData, pieces: tuple[Piece, ...]
) -> dict[str, np.ndarray]:
    """Name -> (x, y, z, qw, qx, qy, qz) of each piece's free joint."""
    out = {}
    for piece in pieces:
        adr = model.jnt_qposadr[model.joint(piece.name).id]
        out[piece.name] = data.qpos[adr : adr + 7].copy()
    return out


def piece_velocities(
    model: mujoco.MjModel, data: mujoco.MjData, pieces: tuple[Piece, ...]
) -> dict[str, np.ndarray]:
    """Name -> the 6 ``qvel`` entries of each piece's free joint (vx, vy, vz [m/s] in the world
    frame, wx, wy, wz [rad/s] in the body frame), as ``settle(velocities=...)`` takes them."""
    out = {}
    for piece in pieces:
        adr = model.jnt_dofadr[model.joint(piece.name).id]
        out[piece.name] = data.qvel[adr : adr + 6].copy()
    return out
