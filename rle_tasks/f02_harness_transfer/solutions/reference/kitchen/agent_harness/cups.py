"""Cups: take one out of the sink basin, set it on a burner (``cup_from_sink``, ``cup_to_burner``).

The basin's floor lies about 0.2 m below the counter tops and its middle about 0.33 m in front of the
wall: the base stands as close to the run as its deck allows and the cup is picked top-down like any
object, the fingers 2 cm below its rim.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .geometry import quat_mul, quat_to_mat
from .kitchen import (
    BESIDE_Y,
    COUNTER_Z,
    EMPTY,
    FINGER_CLEARANCE,
    FRONT_Y,
    GRASP_DEPTH_ROUND,
    PICK_TORSO,
    STAND_Y,
    Held,
)
from .motion import down_quat
from .perception import in_box

if TYPE_CHECKING:
    from .skills import Skills

__all__ = ["burner_centre", "cup_from_sink", "cup_to_burner", "cup_to_rack", "pick_in_basin", "rack_spot"]

CARRY_Z = 1.1
"""Tool height while carrying a cup over the counters [m] (below the wall cabinets, 1.45 m up)."""
NEAR = 0.08
"""Gap between a cup's centre and the basin's nearest wall below which the hand leans away from the
wall [m]: the cup's radius (0.032) plus half the hand's thickness (0.03) and 2 cm of tracking error."""
TILT = 0.35
"""Lean of the hand away from a near wall [rad]: 0.1 m above the fingertips it stands 3.4 cm further off."""
RACK_IN = 0.07
"""Distance of a cup's centre behind the dish rack's front edge [m]: the front region between its front
rail and the tines (0.2 m behind the front) holds a cup 0.064 m across."""
RACK_DROP = 0.015
"""Height of the cup's bottom above the rack's tray when let go [m]."""
PALM = 0.1
"""Gap along the closing axis below which the palm's end (0.1 m from the fingers' middle, 6 cm above
their tips) would sit on the counter's edge beside the basin [m]."""
ROLL = 0.5
"""Rise of the palm's end towards a near wall along the closing axis [rad]: 6 cm above the tips and 0.1 m
out it then stands 0.1 * cos 0.5 - 0.06 * sin 0.5 = 0.059 m out, 0.1 m up."""
LIFT = 0.2
"""Lift of the cup out of the basin [m] (its floor is 0.2 m below the counter tops)."""
BURNER_DROP = 0.01
"""Height of the cup's bottom above the burner when let go [m]."""


def cup_from_sink(sk: Skills, prompt: str = "cup") -> Held | None:
    """Find the sink basin, stand in front of the cup lying in it and pick it (``pick_in_basin``)."""
    basin = sk.search("sink basin", (-np.inf, -np.inf, 0.6), (np.inf, 0.0, 0.95), radius=None)
    if len(basin) < 10:
        sk.note("no sink basin in sight")
        return None
    lo_xy, hi_xy = np.percentile(basin[:, :2], 5, axis=0), np.percentile(basin[:, :2], 95, axis=0)
    mid, floor = (lo_xy + hi_xy) / 2, float(np.percentile(basin[:, 2], 3))
    sk.note(f"sink basin at {np.round(mid, 3)}, extent {np.round(hi_xy - lo_xy, 3)}, floor {floor:.2f}")
    sk.tuck()
    sk.goto(float(mid[0]), BESIDE_Y)
    lo = (mid[0] - 0.35, FRONT_Y, floor - 0.05)
    hi = (mid[0] + 0.35, 0.0, COUNTER_Z + 0.1)
    pts = sk.find(prompt, lo, hi)
    if len(pts) < 3:
        sk.note(f"no {prompt} in the sink")
        return None
    guess = np.array([*np.median(pts[:, :2], axis=0), np.percentile(pts[:, 2], 95)])
    sk.note(f"{prompt} in the sink near {np.round(guess, 3)}")
    if abs(guess[0] - sk.obs["base_pos"][0]) > 0.1:
        sk.tuck()
        sk.goto(float(guess[0]), BESIDE_Y, lane=False)
    return pick_in_basin(sk, prompt, guess, (lo_xy, hi_xy))


def _walls(
    sk: Skills, xy: np.ndarray, extent: tuple[np.ndarray, np.ndarray]
) -> list[tuple[np.ndarray, float]]:
    """(unit (x, y) from ``xy`` towards the basin's wall, the gap to it [m]) along the base's heading and
    across it (the robot faces the run, so the basin's walls run along these axes), nearest first."""
    yaw = float(sk.obs["base_yaw"])
    lo, hi = extent
    mid, half = (lo + hi) / 2, (hi - lo) / 2
    out = []
    for axis in (np.array([np.cos(yaw), np.sin(yaw)]), np.array([-np.sin(yaw), np.cos(yaw)])):
        off = float((xy - mid) @ axis)
        out.append((axis * (1.0 if off >= 0 else -1.0), float(np.abs(half @ axis)) - abs(off)))
    return sorted(out, key=lambda wg: wg[1])


def pick_in_basin(
    sk: Skills, prompt: str, guess: np.ndarray, extent: tuple[np.ndarray, np.ndarray]
) -> Held | None:
    """Grasp an upright cup on the basin's floor near ``guess`` [m] (``extent``: the basin's (x, y) corners
    [m]): a close look from above, then the fingers close along the nearest wall with the hand leaning
    ``TILT`` away from it when the cup stands within ``NEAR`` of it (the hand is 6 cm thick across its
    closing axis, the counter's edge 0.2 m above the floor); approached along the tool's axis."""
    top = float(guess[2])
    sk.motion.set_torso(PICK_TORSO)
    for attempt in range(2):
        pts = sk.close_look(prompt, np.asarray(guess[:2]), top)
        if len(pts) < 5:
            sk.note(f"pick: no close view of {prompt}")
            return None
        top = float(np.percentile(pts[:, 2], 95))
        cap = in_box(pts, (-np.inf, -np.inf, top - 0.012), (np.inf, np.inf, np.inf))
        xy = cap[:, :2].mean(axis=0) if len(cap) >= 3 else np.median(pts[:, :2], axis=0)
        ring = sk._support(np.array([*xy, top]), pts)
        (w, gap), (w2, gap2) = _walls(sk, xy, extent)
        home = float(sk.obs["base_yaw"]) + np.pi / 2
        yaw = float(np.arctan2(w[1], w[0])) - np.pi / 2  # closing axis along the wall, lean towards w
        pitch = TILT if gap < NEAR else 0.0
        if np.cos(yaw - home) < 0:  # the same grasp turned half a turn: nearer the arm's home
            yaw, pitch = yaw + np.pi, -pitch
        q = down_quat(yaw, pitch)
        roll = 0.0
        if gap2 < PALM:  # a corner: raise the end of the palm that points at the other wall
            a = np.array([w[0], w[1], 0.0])  # horizontal, across the closing axis
            roll = ROLL * float(np.sign(a[0] * w2[1] - a[1] * w2[0]))
            q = quat_mul(np.array([np.cos(roll / 2), *(np.sin(roll / 2) * a)]), q)
        z = max(top - GRASP_DEPTH_ROUND, ring + FINGER_CLEARANCE)
        target = np.array([xy[0], xy[1], z])
        axis = quat_to_mat(q)[:, 2]
        sk.motion.move_tool(target - 0.1 * axis, q, tol=0.01, max_steps=120, speed=0.5, gripper=-1.0)
        sk.motion.move_tool(target - 0.1 * axis, q, tol=0.004, max_steps=30, speed=0.3, correct=True)
        sk.motion.move_tool(target, q, tol=0.004, max_steps=80, speed=0.3, correct=True)
        sk.note(
            f"grasp {prompt} in basin: target {np.round(target, 3)} yaw {yaw:.2f} pitch {pitch:.2f} roll {roll:.2f} gaps {gap:.3f} {gap2:.3f} tool {np.round(sk.obs['ee_pos'], 3)}"
        )
        o = sk.motion.close_gripper(steps=10)
        if o["gripper"] > EMPTY:
            held = Held(prompt, float(o["ee_pos"][2] - ring))
            sk.motion.move_tool_by([0.0, 0.0, LIFT], tol=0.02, max_steps=60, gripper=1.0)
            if pitch:  # upright again, clear of the basin
                sk.motion.move_tool(sk.obs["ee_pos"], down_quat(yaw), tol=0.02, max_steps=40, gripper=1.0)
            if sk.obs["gripper"] > EMPTY:
                sk.note(f"picked {prompt} at {np.round(xy, 3)} (support {ring:.2f})")
                return held
        sk.note(f"pick {prompt}: missed (attempt {attempt}, opening {sk.obs['gripper']:.4f})")
        sk.motion.open_gripper(steps=6)
        sk.tuck()
        guess = np.array([xy[0], xy[1], top])
    return None


def burner_centre(sk: Skills, burner: str) -> np.ndarray | None:
    """(x, y, top z) [m] of the ``burner`` ("front left" ...) on the cooktop, or None."""
    prompt = f"{burner} burner"
    lo, hi = (-np.inf, -np.inf, COUNTER_Z - 0.05), (np.inf, 0.0, COUNTER_Z + 0.15)
    pts = sk.search(prompt, lo, hi, radius=0.12)
    if len(pts) < 3:
        return None
    mid = (np.percentile(pts[:, :2], 5, axis=0) + np.percentile(pts[:, :2], 95, axis=0)) / 2
    return np.array([*mid, np.percentile(pts[:, 2], 90)])


def cup_to_burner(sk: Skills, held: Held, centre: np.ndarray) -> bool:
    """Carry the held cup to the burner at ``centre`` (``burner_centre``) and set it down on it."""
    sk.carry_pose()
    sk.goto(float(centre[0]), BESIDE_Y)
    sk.place(held, centre[:2], float(centre[2]), drop=BURNER_DROP, carry_z=CARRY_Z)
    # Back off before anything else: from the look pose here the arm would hit the range hood.
    sk.home()
    sk.goto(float(sk.obs["base_pos"][0]), STAND_Y, lane=False)
    return True


def rack_spot(sk: Skills) -> np.ndarray | None:
    """(x, y, tray top z) [m] where a cup stands in the dish rack: its middle across the run, ``RACK_IN``
    from its front edge (between the front rail and the tines at the back), or None when not seen."""
    pts = sk.search(
        "dish rack", (-np.inf, -np.inf, COUNTER_Z - 0.05), (np.inf, 0.0, COUNTER_Z + 0.2), radius=0.3
    )
    if len(pts) < 10:
        return None
    yaw = float(sk.obs["base_yaw"])
    fwd, lat = np.array([np.cos(yaw), np.sin(yaw)]), np.array([-np.sin(yaw), np.cos(yaw)])
    along, ahead = pts[:, :2] @ lat, pts[:, :2] @ fwd
    mid = (np.percentile(along, 3) + np.percentile(along, 97)) / 2
    front = float(np.percentile(ahead, 3))
    xy = mid * lat + (front + RACK_IN) * fwd
    return np.array([*xy, np.percentile(pts[:, 2], 5)])


def cup_to_rack(sk: Skills, held: Held, spot: np.ndarray) -> bool:
    """Carry the held cup to ``spot`` (``rack_spot``) and stand it in the dish rack."""
    sk.carry_pose()
    sk.goto(float(spot[0]), BESIDE_Y)
    sk.place(held, spot[:2], float(spot[2]), drop=RACK_DROP, carry_z=CARRY_Z)
    sk.home()
    return True
