"""Bowls: grasp one by its rim, tip out what lies in it, put it into the sink.

A bowl (about 0.17 m across, 0.06 m high, thin tilted walls) is too wide for the fingers (at most
0.08 m apart), so it is held by its rim: the tool pointing down over the rim point nearest the base,
the fingers closing across the wall (radially). Rolling the tool about that closing axis tips the bowl
about its own diameter, so whatever lies in it falls out to one side.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .geometry import quat_mul
from .kitchen import COUNTER_Z, PICK_TORSO, Held
from .motion import down_quat
from .perception import HAND, clean, in_box
from .skills import Skills

__all__ = ["RIM_HELD", "Bowl", "bowl_to_sink", "dump_bowl", "find_bowl", "grasp_rim", "sink_basin"]

RIM_DEPTH = 0.02
"""Depth of the fingertips below the rim's top [m]."""
RIM_HELD = 0.002
"""Finger opening [m] above which the fingers hold the wall (it is 6 mm thick, met at a slant)."""
RIM_LOOK = 0.3
"""Height of the close look above the rim [m] (the whole bowl in the eye-in-hand view)."""
DUMP_LIFT = 0.2
"""Lift of the rim above its resting height before tipping [m] (the bowl's side sweeps 0.09 m down)."""
DUMP_TILT = 1.9
"""Turn of the tool's axis from straight down that tips the bowl over [rad] (its walls lean 0.35 rad in)."""
RIM_OPEN = 0.028
"""Finger opening while reaching over the rim [m]: narrow, so the inner finger stays clear of the leftovers."""
RIM_OUT = 0.004
"""Grasp this far outside the rim's top [m] (the walls lean inwards: lower down they lie further out)."""
SINK_MARGIN = 0.03
"""Height of the bowl's bottom above the counter tops when let go over the sink basin [m]."""


@dataclass(frozen=True)
class Bowl:
    """A bowl seen from above: ``center`` (x, y) [m], ``rim_z`` its rim's top [m], ``radius`` of the rim
    [m], ``support_z`` the surface it stands on [m]."""

    center: np.ndarray
    rim_z: float
    radius: float
    support_z: float


def sink_basin(sk: Skills) -> tuple[np.ndarray, float] | None:
    """((x, y) of the sink basin's middle [m], its floor's height [m]) from the views now, or None."""
    basin = sk.find("sink basin", (-np.inf, -np.inf, 0.6), (np.inf, 0.0, 0.95), radius=None)
    if len(basin) < 10:
        return None
    mid = (np.percentile(basin[:, :2], 5, axis=0) + np.percentile(basin[:, :2], 95, axis=0)) / 2
    return mid, float(np.percentile(basin[:, 2], 3))


def find_bowl(sk: Skills, guess: np.ndarray) -> Bowl | None:
    """The bowl near ``guess`` (x, y, top z) [m] seen by the eye-in-hand camera from ``RIM_LOOK`` above
    its rim, looking straight down: the rim's centre is the middle of its highest points' extent."""
    q = down_quat(sk.obs["base_yaw"] + np.pi / 2)
    top = float(guess[2])
    sk.motion.move_tool([guess[0], guess[1], top + RIM_LOOK], q, tol=0.02, max_steps=120)
    lo = (guess[0] - 0.2, guess[1] - 0.2, top - 0.2)
    hi = (guess[0] + 0.2, guess[1] + 0.2, top + 0.1)
    pts = clean(sk.see("bowl", lo, hi, cameras=(HAND,), tries=4), 0.15)
    if len(pts) < 20:
        sk.note(f"bowl: no close view ({len(pts)} points)")
        return None
    rim_z = float(np.percentile(pts[:, 2], 98))
    rim = in_box(pts, (-np.inf, -np.inf, rim_z - 0.012), (np.inf, np.inf, np.inf))
    if len(rim) < 10:
        rim = pts
    lo_xy, hi_xy = np.percentile(rim[:, :2], 1, axis=0), np.percentile(rim[:, :2], 99, axis=0)
    center = (lo_xy + hi_xy) / 2
    radius = float(np.mean(hi_xy - lo_xy)) / 2
    support = sk._support(np.array([*center, rim_z]), pts)
    bowl = Bowl(center, rim_z, radius, support)
    sk.note(f"bowl at {np.round(center, 3)} rim z {rim_z:.3f} radius {radius:.3f} support {support:.3f}")
    return bowl


def grasp_rim(sk: Skills, bowl: Bowl) -> tuple[Held, float] | None:
    """Grip the rim point farthest from the base and lift the bowl by ``DUMP_LIFT``: returns (what is held,
    the grasp's yaw [rad], the closing axis pointing away from the base) or None when the fingers closed
    on nothing."""
    away = bowl.center - np.asarray(sk.obs["base_pos"][:2], float)
    u = away / max(float(np.linalg.norm(away)), 1e-6)
    yaw = float(np.arctan2(u[1], u[0]))
    xy = bowl.center + (bowl.radius + RIM_OUT) * u
    z = bowl.rim_z - RIM_DEPTH
    q = down_quat(yaw)
    narrow = 1.0 - 2.0 * RIM_OPEN / 0.08  # the gripper command is linear in the opening (0.08 m: -1)
    sk.motion.set_torso(PICK_TORSO)
    sk.motion.move_tool([xy[0], xy[1], z + 0.1], q, tol=0.01, max_steps=120, speed=0.5, gripper=narrow)
    sk.motion.move_tool([xy[0], xy[1], z + 0.05], q, tol=0.005, max_steps=40, speed=0.3, correct=True)
    sk.motion.move_tool([xy[0], xy[1], z], q, tol=0.004, max_steps=60, speed=0.3, correct=True)
    o = sk.motion.close_gripper(steps=10)
    sk.note(
        f"rim grasp at {np.round([*xy, z], 3)} yaw {yaw:.2f}: tool {np.round(o['ee_pos'], 3)}, opening {o['gripper']:.4f}"
    )
    if float(o["gripper"]) <= RIM_HELD:
        sk.motion.open_gripper(steps=6)
        sk.motion.move_tool_by([0.0, 0.0, 0.15], tol=0.03, max_steps=40)
        return None
    held = Held("bowl", float(o["ee_pos"][2]) - bowl.support_z)
    sk.motion.move_tool_by([0.0, 0.0, DUMP_LIFT], tol=0.02, max_steps=60, gripper=1.0)
    if float(sk.obs["gripper"]) <= RIM_HELD:
        sk.note("bowl slipped out while lifting")
        return None
    return held, yaw


def _tipped(yaw: float, angle: float) -> np.ndarray:
    """The rim grasp's orientation (``down_quat(yaw)``) with the tool's axis turned by ``angle`` [rad] from
    straight down towards the closing axis (the bowl, hanging behind the grip, turns its opening to the
    base)."""
    u = np.array([np.cos(yaw), np.sin(yaw), 0.0])
    n = np.cross([0.0, 0.0, -1.0], u)
    turn = np.array([np.cos(angle / 2), *(np.sin(angle / 2) * n)])
    return quat_mul(turn, down_quat(yaw))


def dump_bowl(sk: Skills, yaw: float) -> None:
    """Tip the bowl held by its far rim (closing axis ``yaw`` [rad], away from the base) over and back: the
    tool's axis turns from down towards the closing axis by ``DUMP_TILT``, so the bowl hangs below the grip
    with its opening to the base and its contents fall out in front of it."""
    pos = np.asarray(sk.obs["ee_pos"], float).copy()
    for angle in (0.6, 1.2, DUMP_TILT):
        sk.motion.move_tool(pos, _tipped(yaw, angle), tol=0.03, rot_tol=0.1, max_steps=40, gripper=1.0)
    sk.motion.wait(15)
    sk.note(f"tipped the bowl: tool {np.round(sk.obs['ee_pos'], 3)}, opening {sk.obs['gripper']:.4f}")
    for angle in (1.0, 0.0):
        sk.motion.move_tool(pos, _tipped(yaw, angle), tol=0.03, rot_tol=0.1, max_steps=40, gripper=1.0)


def bowl_to_sink(
    sk: Skills, held: Held, bowl: Bowl, yaw: float, basin: tuple[np.ndarray, float], beside_y: float
) -> None:
    """Carry the bowl held at its rim (grasp ``yaw`` [rad]) over the sink basin's middle and let it go
    ``SINK_MARGIN`` above counter height (it falls in)."""
    mid, _ = basin
    u = np.array([np.cos(yaw), np.sin(yaw)])
    sk.carry_pose()
    sk.goto(float(mid[0]), beside_y)
    sk.place(held, mid + bowl.radius * u, COUNTER_Z, drop=SINK_MARGIN, carry_z=1.1)
