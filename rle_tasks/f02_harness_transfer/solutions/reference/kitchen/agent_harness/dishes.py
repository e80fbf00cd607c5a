"""Bowls: take what lies in one out, grip it by its rim, put it into the sink.

A bowl (about 0.17 m across, 0.06 m high, thin walls leaning inwards to a rim about 0.12 m across) is too
wide for the fingers (at most 0.08 m apart), so it is held by its rim: the tool pointing down over the
rim at the bowl's side, the fingers closing across the wall. Tipping it out does not work: the arm turns
the hand about 105 degrees at most, and two leftovers wedge under the inward-leaning walls; so they are
picked out one by one, the fingers opened only a little wider than each (they stay inside the rim).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .kitchen import COUNTER_Z, EMPTY, FINGER_CLEARANCE, GRASP_DEPTH, GRASP_DEPTH_ROUND, PICK_TORSO, Held
from .motion import down_quat
from .perception import HAND, clean, clouds, in_box
from .skills import Skills

__all__ = [
    "RIM_HELD",
    "Bowl",
    "bowl_to_sink",
    "empty_bowl",
    "find_bowl",
    "grasp_rim",
    "leftovers",
    "pick_leftover",
    "sink_basin",
]

RIM_DEPTH = 0.02
"""Depth of the fingertips below the rim's top [m]."""
RIM_HELD = 0.002
"""Finger opening [m] above which the fingers hold the wall (it is 6 mm thick, met at a slant)."""
RIM_LOOK = 0.3
"""Height of the close look above the rim [m] (the whole bowl in the eye-in-hand view)."""
RIM_LIFT = 0.15
"""Lift of the bowl held by its rim [m]."""
RIM_OPEN = 0.028
"""Finger opening while reaching over the rim [m]: narrow, so the inner finger stays clear of the leftovers."""
RIM_OUT = 0.004
"""Grasp this far outside the rim's top [m] (the walls lean inwards: lower down they lie further out)."""
LEFTOVER_GAP = 0.02
"""Finger opening beyond an object's width when reaching into the bowl for it [m]."""
BLOCKED = 0.015
"""Height of the tool above its grasp target at which a reach into the bowl counts as blocked [m]."""
FINGER_HALF = 0.01
"""Half a finger's thickness along the closing axis [m]."""
BOWL_FLOOR = 0.006
"""Thickness of the bowl's bottom [m]."""
SET_DOWN = 0.22
"""Distance from the bowl's centre where the first object taken out of it is set down [m]."""
MAX_LEFTOVERS = 5
"""Attempts at taking an object out of the bowl [-]."""
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


def grasp_rim(sk: Skills, bowl: Bowl) -> tuple[Held, np.ndarray] | None:
    """Grip the rim at the bowl's side (seen from the base), the fingers closing across the wall along the
    base's lateral axis (the arm's home yaw), and lift the bowl by ``RIM_LIFT``: returns (what is held, the
    unit (x, y) from the bowl's centre to the grip) or None when the fingers closed on nothing."""
    yaw = float(sk.obs["base_yaw"]) + np.pi / 2
    u = np.array([np.cos(yaw), np.sin(yaw)])
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
    sk.motion.move_tool_by([0.0, 0.0, RIM_LIFT], tol=0.02, max_steps=60, gripper=1.0)
    if float(sk.obs["gripper"]) <= RIM_HELD:
        sk.note("bowl slipped out while lifting")
        return None
    return held, u


def leftovers(sk: Skills, bowl: Bowl, prompts: tuple[str, ...]) -> list[tuple[str, np.ndarray]]:
    """(prompt, points [m]) of each object instance of ``prompts`` seen lying in the bowl from ``RIM_LOOK``
    above it (the eye-in-hand camera looking down; one entry per instance: two lemons are two entries)."""
    q = down_quat(sk.obs["base_yaw"] + np.pi / 2)
    sk.motion.move_tool([*bowl.center, bowl.rim_z + RIM_LOOK], q, tol=0.02, max_steps=120)
    r = bowl.radius + 0.01
    lo, hi = (-np.inf, -np.inf, bowl.support_z), (np.inf, np.inf, bowl.rim_z + 0.1)
    found: list[tuple[str, np.ndarray]] = []
    for attempt in range(2):
        for prompt in prompts:
            for _, pts in clouds(sk.client, sk.obs, prompt, (HAND,)):
                pts = in_box(pts, lo, hi)
                pts = pts[np.linalg.norm(pts[:, :2] - bowl.center, axis=1) < r] if len(pts) else pts
                if len(pts) >= 8:
                    found.append((prompt, clean(pts, 0.05)))
        if found or attempt:
            break
        sk.motion.wait(1)  # the segmenter misses small instances at times: a new image
    return found


def _leftover_grasp(
    pts: np.ndarray, bowl: Bowl, yaw: float, round_: bool
) -> tuple[np.ndarray, float, float, float]:
    """(grasp (x, y) [m], yaw [rad], finger opening [m], clearance of the fingers from the rim [m]) of an
    object in the bowl: across its narrower side, or for a round one at the yaw that keeps the fingers
    farthest inside the rim."""
    top = float(np.percentile(pts[:, 2], 95))
    cap = in_box(pts, (-np.inf, -np.inf, top - 0.012), (np.inf, np.inf, np.inf))
    xy = cap[:, :2].mean(axis=0) if len(cap) >= 3 else np.median(pts[:, :2], axis=0)
    best = (xy, yaw, 0.08, -np.inf)
    if round_:  # nearly round seen from above: open for its widest side whatever the yaw
        spread = max(
            float(np.ptp(np.percentile((pts[:, :2] - xy) @ [np.cos(y), np.sin(y)], [5, 95])))
            for y in np.linspace(0.0, np.pi, 8, endpoint=False)
        )
    for y in (yaw + np.linspace(0.0, np.pi, 12, endpoint=False)) if round_ else (yaw,):
        a = np.array([np.cos(y), np.sin(y)])
        across = (pts[:, :2] - xy) @ a
        width = spread if round_ else float(np.percentile(across, 95) - np.percentile(across, 5))
        opening = min(0.07, width + LEFTOVER_GAP)
        for t in np.linspace(-1.0, 1.0, 5) * (
            LEFTOVER_GAP / 2 - 0.003
        ):  # the object stays between the fingers
            g = xy + t * a
            reach = max(
                np.linalg.norm(g + s * (opening / 2 + FINGER_HALF) * a - bowl.center) for s in (-1, 1)
            )
            if bowl.radius - reach > best[3]:
                best = (g, float(y), opening, float(bowl.radius - reach))
    return best


def pick_leftover(sk: Skills, prompt: str, pts: np.ndarray, bowl: Bowl) -> Held | None:
    """Grasp an object lying in the bowl from above (``_leftover_grasp``), the fingers opened only
    ``LEFTOVER_GAP`` wider than it (they stay inside the rim), and lift it clear of the rim."""
    top = float(np.percentile(pts[:, 2], 95))
    yaw, round_ = sk._grasp_yaw(in_box(pts, (-np.inf, -np.inf, top - 0.03), (np.inf, np.inf, np.inf)))
    xy, yaw, opening, clear = _leftover_grasp(pts, bowl, yaw, round_)
    narrow = 1.0 - 2.0 * opening / 0.08
    floor = bowl.support_z + BOWL_FLOOR
    z = max(top - (GRASP_DEPTH_ROUND if round_ else GRASP_DEPTH), floor + FINGER_CLEARANCE)
    q = down_quat(yaw)
    sk.motion.move_tool([xy[0], xy[1], z + 0.1], q, tol=0.01, max_steps=120, speed=0.5, gripper=narrow)
    sk.motion.move_tool([xy[0], xy[1], z + 0.05], q, tol=0.005, max_steps=40, speed=0.3, correct=True)
    sk.motion.move_tool([xy[0], xy[1], z], q, tol=0.004, max_steps=60, speed=0.3)
    if float(sk.obs["ee_pos"][2]) > z + BLOCKED:  # a finger rests on the rim or another object
        sk.note(
            f"grasp {prompt} in the bowl blocked at {np.round(sk.obs['ee_pos'], 3)} for {np.round([*xy, z], 3)} "
            f"yaw {yaw:.2f} opening {opening:.3f} clearance {clear:.3f}"
        )
        sk.motion.move_tool_by([0.0, 0.0, 0.1], tol=0.03, max_steps=30)
        return None
    o = sk.motion.close_gripper(steps=10)
    sk.note(
        f"grasp {prompt} in the bowl at {np.round([*xy, z], 3)} yaw {yaw:.2f} opening {opening:.3f} "
        f"clearance {clear:.3f}: tool {np.round(o['ee_pos'], 3)}, fingers {o['gripper']:.4f}"
    )
    if float(o["gripper"]) <= EMPTY:
        sk.motion.open_gripper(steps=6)
        sk.motion.move_tool_by([0.0, 0.0, 0.15], tol=0.03, max_steps=40)
        return None
    held = Held(prompt, float(o["ee_pos"][2]) - floor)
    sk.motion.move_tool_by([0.0, 0.0, 0.15], tol=0.02, max_steps=50, gripper=1.0)
    return held if float(sk.obs["gripper"]) > EMPTY else None


def _clearance(sk: Skills, pts: np.ndarray, bowl: Bowl) -> float:
    top = float(np.percentile(pts[:, 2], 95))
    yaw, round_ = sk._grasp_yaw(in_box(pts, (-np.inf, -np.inf, top - 0.03), (np.inf, np.inf, np.inf)))
    return _leftover_grasp(pts, bowl, yaw, round_)[3]


def empty_bowl(sk: Skills, bowl: Bowl, prompts: tuple[str, ...], away: np.ndarray) -> int:
    """Take every object of ``prompts`` out of the bowl and put it on the counter ``SET_DOWN`` (then 0.1 m
    further for each next one) from the bowl's centre along the unit (x, y) ``away``; returns how many
    were set down."""
    done, failed = 0, []
    for _ in range(MAX_LEFTOVERS):
        seen = leftovers(sk, bowl, prompts)
        if not seen:
            break

        def score(f: tuple[str, np.ndarray]) -> float:  # clearance; less near a spot that failed
            c = np.median(f[1][:, :2], axis=0)
            return _clearance(sk, f[1], bowl) - 0.05 * sum(np.linalg.norm(c - x) < 0.03 for x in failed)

        prompt, pts = max(seen, key=score)
        held = pick_leftover(sk, prompt, pts, bowl)
        if held is None:
            failed.append(np.median(pts[:, :2], axis=0))
            sk.tuck()
            continue
        spot = bowl.center + (SET_DOWN + 0.1 * done) * away
        sk.place(held, spot, bowl.support_z, drop=0.01)
        done += 1
    sk.note(f"took {done} objects out of the bowl")
    return done


def bowl_to_sink(
    sk: Skills, held: Held, bowl: Bowl, u: np.ndarray, basin: tuple[np.ndarray, float], beside_y: float
) -> None:
    """Carry the bowl held at its rim (``u``: unit (x, y) from its centre to the grip) over the sink basin's
    middle and let it go ``SINK_MARGIN`` above counter height (it falls in)."""
    mid, _ = basin
    sk.carry_pose()
    sk.goto(float(mid[0]), beside_y)
    sk.place(held, mid + bowl.radius * u, COUNTER_Z, drop=SINK_MARGIN, carry_z=1.1)
