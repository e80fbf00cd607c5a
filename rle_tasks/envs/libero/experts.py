"""State-based scripted experts for LIBERO-10 (they make family 05's demonstrations).

An expert reads the simulator's state (``LiberoEnv.scene``: end effector, object poses and collision
boxes, region sites, articulated joints, the BDDL goal), never an image, and drives the robot through
the policy interface: 7-D OSC actions at 20 Hz. It turns each goal predicate into a skill:

- ``in``/``on`` object, region-or-object: pick the object from above (fingers across its narrower
  side where the hand fits, else at an angle or at its rim) and release it above the target;
- ``in`` a region behind a hinged door: pinch the object's outward part (a mug's handle) with the
  hand pointing through the opening, carry it in, back out;
- ``close`` a drawer: push it shut along its slide; a hinged door: swing it shut along its arc;
- ``turnon`` a stove: pinch the knob's bar and turn it about the knob's axis.

``supported(scene)`` tells whether every predicate of a task's goal has a skill: every LIBERO-10
task has (success rates per task in the README).

Each skill is a generator of actions; ``run_expert`` chains the skills of the goal in an order that
keeps them feasible (a drawer is filled before it is closed) and stops at success or the horizon.
Randomness (start jitter, grasp offsets) comes from the caller's seeded generator, so demonstrations
are reproducible.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from rle_tasks.envs.libero import LiberoEnv

__all__ = ["ExpertResult", "run_expert", "supported"]

POS_STEP = 0.05
"""Largest end-effector displacement of one action unit [m] (robosuite OSC ``output_max``)."""
ROT_STEP = 0.5
"""Largest rotation of one action unit [rad]."""
OPEN, CLOSED = -1.0, 1.0
FINGER_AXIS = 0
"""Axis of the end-effector site frame along which the Panda's fingers close."""
MAX_GRASP_WIDTH = 0.07
"""Widest object span the open fingers take with room to spare [m] (the Panda opens to 0.08 m)."""
HAND_HALF, HAND_WIDTH = 0.11, 0.07
"""Footprint of the Panda hand with open fingers: half-length along the fingers, width across [m]."""
HAND_LIFT = 0.005
"""Height of the hand's collision body above the grasp point (the finger pads' centre) [m]."""
WALL_IN, RIM_DEPTH = 0.006, 0.025
"""A rim grasp holds the wall this far inside the outer surface and this far below the top [m]."""
PUSH_GAP = 0.03
"""Gap between the fingers and a drawer's face before a push [m]."""
KNOB_TURN, KNOB_STEPS, KNOB_DEPTH = 0.9, 9, 0.015
"""A knob is turned by this angle [rad] in this many way points, gripped this far below its top [m]."""
DRAWER_FRONT_SHIFT = 0.025
"""How far in front of a drawer region's centre objects are released [m]."""
PUSH_TILT = 0.6
"""Tilt of the fingers towards a push from pointing down [rad]."""
PUSH_TRIES = 3
"""Pushes at a drawer before the expert moves on."""
HIGH_GRASP_DEPTH = 0.012
"""A repeated grasp holds the object this far below its top, at its body's axis [m]."""
SLOT_SPACING, SLOT_GAP = 0.08, 0.01
"""Distance between objects released into the same region [m], widened to an object's extent along
the row plus the gap where it is wider (two moka pots, 0.081 m across, on a 0.15 m cook region)."""
GRASP_TRIES = 3
"""Attempts at one grasp before the expert moves on."""
HINGE_PUSH_AT = 0.75
"""Where the fingers push a hinged door: this fraction of the door's reach from its hinge [1]."""
HINGE_STEP, HINGE_GAP, HINGE_PAST = 0.2, 0.01, 0.4
"""Door angle between two way points of a hinged-door push [rad]; gap between the hand's side and
the door's outer face (with its handle) before the push [m]; the way points run this far past
closed [rad]: the hand stands off the door by its handle's thickness, which the door is thinner
than where the hand pushes (6.4 cm measured on the microwave: 0.15 rad past left it at -0.03 rad,
not closed)."""
HAND_BACK, STAGE_OFF = 0.22, 0.10
"""A hand pointing horizontally, with its forearm, occupies this far behind its grip point [m]
(task 9: at 0.17 m the hand met the other mug); an object whose grasp it would block is first set
down this far in front of the region behind the door [m]."""
DOOR_APPROACH, DOOR_CLEARANCE, DOOR_DEPTH = 0.07, 0.02, 0.075
"""Placing through a door: approach and back-out distance in front of the pinched part and of the
opening [m]; the object's bottom lifted this far over the region's floor [m]; its body carried
this far past the region's front [m], or until the hand meets the door's frame (task 9: the hand
stops first, the mug's body 5.5 cm past the front)."""
SETTLE_STEPS = 20
"""Steps held after the last skill for released objects to come to rest (success is checked per step)."""
STALL_STEPS, STALL_CENTRED = 8, 0.008
"""A descent also ends when the hand has not moved 1 mm up or down in this many steps while within
this horizontal distance of its point [m]: fingers resting on a rim, pushed to and fro across the
centring tolerance (measured on task 8: 37 steps held at a moka pot's lid)."""
HIGH_FIRST = ("moka_pot",)
"""Objects whose first grasp is the high one (at the body's axis, below the top): a moka pot's handle
and spout rise above its body and stop the hand of a grasp across its box (task 8)."""


@dataclass(frozen=True)
class ExpertResult:
    success: bool
    steps: int
    actions: np.ndarray
    """(steps, 7) the actions sent."""
    log: tuple[str, ...] = ()
    """One line per skill: what it did and what it left (for statistics and debugging)."""
    sim_states: np.ndarray | None = None
    """(steps + 1, n) MuJoCo states before each action and after the last (when recorded)."""
    observations: np.ndarray | None = None
    """(steps + 1, 8) the policy's ``state`` observation at the same instants (when recorded)."""
    views: dict[str, np.ndarray] | None = None
    """``agentview`` and ``wrist``, uint8 (len(view_frames), H, W, 3): the images the policy would
    have seen at the frames ``view_frames`` (when recorded with a rendering environment)."""
    executed: np.ndarray | None = None
    """(steps, 7) the actions executed when noise was injected (``actions`` then holds the expert's
    clean actions: the labels); None without noise, when the two are the same."""
    view_frames: np.ndarray | None = None
    """Frames (0 .. steps) whose views were recorded: every ``view_every``-th (when views were)."""


def _axis_angle(rot: np.ndarray) -> np.ndarray:
    """Rotation vector of a rotation matrix [rad]."""
    c = np.clip((np.trace(rot) - 1.0) / 2.0, -1.0, 1.0)
    angle = np.arccos(c)
    if angle < 1e-9:
        return np.zeros(3)
    axis = np.array([rot[2, 1] - rot[1, 2], rot[0, 2] - rot[2, 0], rot[1, 0] - rot[0, 1]])
    n = np.linalg.norm(axis)
    if n < 1e-9:  # angle ~ pi: the axis from the symmetric part
        w, v = np.linalg.eigh(rot)
        axis = v[:, np.argmax(w)]
        return axis * angle
    return axis / n * angle


def _rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rotation matrix about a unit ``axis`` (Rodrigues)."""
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    return np.eye(3) + np.sin(angle) * k + (1.0 - np.cos(angle)) * k @ k


def _rz(yaw: float) -> np.ndarray:
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


class _Driver:
    """Closes the loop between skills and the environment, one action per control step."""

    def __init__(
        self,
        env: LiberoEnv,
        horizon: int,
        first_obs: dict,
        record: bool = False,
        noise: float = 0.0,
        rng: np.random.Generator | None = None,
        view_every: int = 1,
    ) -> None:
        self.env, self.horizon, self.record = env, horizon, record
        self.view_every = max(1, int(view_every))
        self.view_frames: list[int] = [0]
        self.noise, self.rng = float(noise), rng
        self.executed: list[np.ndarray] = []
        self.scene = env.scene()
        self.sim_states: list[np.ndarray] = [env.sim_state()] if record else []
        self.observations: list[np.ndarray] = [first_obs["state"]] if record else []
        self.views: dict[str, list[np.ndarray]] = (
            {v: [first_obs[v]] for v in ("agentview", "wrist")} if record and "agentview" in first_obs else {}
        )
        self.down = self.scene["eef_rot"].copy()  # the start orientation: fingers down
        self.actions: list[np.ndarray] = []
        self.success = False
        self.log: list[str] = []
        self.grasp: tuple = ()

    @property
    def done(self) -> bool:
        return self.success or len(self.actions) >= self.horizon

    def act(self, action: np.ndarray) -> None:
        # float32 as stored in demonstrations (and as a policy serves): a replay is then exact
        action = np.asarray(action, dtype=np.float32).astype(np.float64)
        sent = action
        if self.noise > 0.0:  # DART: execute a perturbed action, keep the expert's as the label
            kick = np.r_[self.rng.normal(0.0, self.noise, 6), 0.0]  # the gripper command stays
            sent = np.clip(action + kick, -1.0, 1.0).astype(np.float32).astype(np.float64)
            self.executed.append(sent)
        frame = len(self.actions) + 1  # the frame this step's observation is
        views = bool(self.views) and frame % self.view_every == 0
        obs, self.success = self.env.step(sent, views=views)
        self.actions.append(np.asarray(action, dtype=np.float64))
        self.scene = self.env.scene()
        if self.record:
            self.sim_states.append(self.env.sim_state())
            self.observations.append(obs["state"])
            if views:
                self.view_frames.append(frame)
                for v, frames in self.views.items():
                    frames.append(obs[v])

    def toward(self, pos: np.ndarray, rot: np.ndarray, grip: float, gain: float = 1.0) -> np.ndarray:
        sc = self.scene
        dp = np.clip(gain * (pos - sc["eef_pos"]) / POS_STEP, -1.0, 1.0)
        dr = np.clip(_axis_angle(rot @ sc["eef_rot"].T) / ROT_STEP, -1.0, 1.0)
        return np.concatenate([dp, dr, [grip]])


def _move(d: _Driver, pos, rot, grip, tol=0.01, max_steps=60, gain=1.0, stall: int = 0) -> Iterator[None]:
    """Towards ``pos`` until within ``tol``; with ``stall`` > 0 also ends when the distance has not
    shrunk by 1 mm in that many steps (something blocks the way)."""
    dist: list[float] = []
    for _ in range(max_steps):
        dist.append(float(np.linalg.norm(d.scene["eef_pos"] - pos)))
        if d.done or dist[-1] < tol or (stall and len(dist) > stall and dist[-stall - 1] - dist[-1] < 0.001):
            return
        d.act(d.toward(np.asarray(pos, float), rot, grip, gain))
        yield


def _descend(
    d: _Driver, point: np.ndarray, rot: np.ndarray, grip: float, max_steps: int = 60
) -> Iterator[None]:
    """Straight down onto ``point``: the horizontal error is removed before the gripper drops further
    (fingers a few mm from an object's side), and the descent ends early when the fingers rest on
    something (no progress for five steps)."""
    heights: list[float] = []  # while descending
    every: list[float] = []  # at every step
    for _ in range(max_steps):
        if d.done:
            return
        e = point - d.scene["eef_pos"]
        if np.linalg.norm(e) < 0.005:
            return
        every.append(float(d.scene["eef_pos"][2]))
        if (
            len(every) > STALL_STEPS
            and np.ptp(every[-STALL_STEPS:]) < 0.001
            and np.hypot(e[0], e[1]) < STALL_CENTRED
        ):
            return  # resting while the last millimetres of centring go back and forth
        target = point.copy()
        # centred within 4 mm for the last 3 cm; higher up a larger error is corrected on the way down
        if np.hypot(e[0], e[1]) > 0.004 + 0.1 * max(0.0, -e[2] - 0.03):
            target[2] = d.scene["eef_pos"][2]  # hold the height until centred
            heights.clear()
        else:
            heights.append(float(d.scene["eef_pos"][2]))
            if len(heights) > 5 and heights[-6] - heights[-1] < 0.001:
                return  # resting on the table or the object
        a = d.toward(target, rot, grip, gain=0.7)
        a[2] = np.clip(a[2], -0.5, 0.5)  # at most 2.5 cm a step near objects
        d.act(a)
        yield


def _hold(d: _Driver, grip: float, steps: int) -> Iterator[None]:
    pos, rot = d.scene["eef_pos"].copy(), d.scene["eef_rot"].copy()
    for _ in range(steps):
        if d.done:
            return
        d.act(d.toward(pos, rot, grip))
        yield


def _world_box(obj: dict) -> tuple[np.ndarray, np.ndarray]:
    """World axis-aligned bounds of an object's collision box."""
    lo, hi = obj["box_lo"], obj["box_hi"]
    corners = np.array([[a, b, c] for a in (lo[0], hi[0]) for b in (lo[1], hi[1]) for c in (lo[2], hi[2])])
    world = obj["pos"] + corners @ obj["rot"].T
    return world.min(0), world.max(0)


def _hand_overlap(center: np.ndarray, finger_dir: np.ndarray, z_bottom: float, others: list[dict]) -> float:
    """Summed overlap [m^2] of the hand's footprint (HAND_HALF along the fingers, HAND_WIDTH/2 across)
    with the horizontal boxes of the objects whose tops rise above the hand's lower face."""
    across = np.array([-finger_dir[1], finger_dir[0]])
    corners = np.array(
        [
            center[:2] + a * HAND_HALF * finger_dir[:2] + b * HAND_WIDTH / 2 * across
            for a in (-1, 1)
            for b in (-1, 1)
        ]
    )
    lo, hi = corners.min(0), corners.max(0)
    total = 0.0
    for o in others:
        olo, ohi = _world_box(o)
        if ohi[2] < z_bottom:
            continue
        w = min(hi[0], ohi[0]) - max(lo[0], olo[0])
        h = min(hi[1], ohi[1]) - max(lo[1], olo[1])
        if w > 0 and h > 0:
            total += w * h
    return total


def _rim_grasp(point, top, narrow, width, others) -> tuple[float, np.ndarray, np.ndarray]:
    """(cost, finger direction, grasp point) pinching the wall of a hollow object at the end of its
    narrower axis: fingers close radially across the wall, RIM_DEPTH below the top."""
    u = np.array([narrow[0], narrow[1], 0.0]) / max(1e-9, np.hypot(narrow[0], narrow[1]))
    best = None
    for sign in (1.0, -1.0):
        p = point + sign * (width / 2 - WALL_IN) * u
        p[2] = top - RIM_DEPTH
        cost = _hand_overlap(p, u, p[2] + HAND_LIFT, others)
        if best is None or cost < best[0]:
            best = (cost, u, p)
    return best


def _grasp_frame(
    d: _Driver, name: str, yaw_jitter: float, high: bool = False
) -> tuple[np.ndarray, np.ndarray, float]:
    """(grasp point, gripper rotation, object height) of a top-down grasp.

    The fingers close across the object's narrower side, or at an angle to it (steps of 15 degrees)
    at which the object still fits between them, and the grasp may move along the object's long side
    (up to 3 cm): the choice keeps the hand's footprint clear of the neighbouring objects that rise
    above its lower face, and otherwise stays closest to a centred grasp across the narrower side.
    """
    sc = d.scene
    obj = sc["objects"][name]
    lo, hi = obj["box_lo"], obj["box_hi"]
    rot = obj["rot"]
    center = obj["pos"] + rot @ ((lo + hi) / 2.0)
    ext = hi - lo
    narrow_i = 0 if ext[0] <= ext[1] else 1
    narrow, wide = rot[:, narrow_i], rot[:, 1 - narrow_i]
    a, b = float(ext[narrow_i]), float(ext[1 - narrow_i])
    top = max(center[2] + abs(rot[2] @ ((hi - lo) / 2.0)), center[2])
    height = float(ext[2])
    point = center.copy()
    point[2] = max(top - min(0.03, 0.5 * height), center[2] - 0.5 * height + 0.01)
    if high:
        point[:2] = obj["pos"][:2]
        point[2] = top - HIGH_GRASP_DEPTH
    others = [o for n, o in sc["objects"].items() if n != name]
    wide_h = np.array([wide[0], wide[1], 0.0]) / max(1e-9, np.hypot(wide[0], wide[1]))
    reach = max(0.0, b / 2 - 0.02)  # the fingers stay 2 cm inside the object's ends
    best = None
    for k in (0, 1, -1, 2, -2, 3, -3, 4, -4, 5, -5, 6):
        th = k * np.pi / 12
        if a * abs(np.cos(th)) + b * abs(np.sin(th)) > MAX_GRASP_WIDTH:
            continue
        fdir = np.cos(th) * narrow + np.sin(th) * wide
        fdir = np.array([fdir[0], fdir[1], 0.0]) / max(1e-9, np.hypot(fdir[0], fdir[1]))
        for shift in (0.0, 0.015, -0.015, 0.03, -0.03):
            if abs(shift) > reach:
                continue
            p = point + shift * wide_h
            cost = _hand_overlap(p, fdir, p[2] + HAND_LIFT, others) + 1e-5 * (abs(k) + 100 * abs(shift))
            if best is None or cost < best[0]:
                best = (cost, fdir, p)
    if best is None:  # wider than the open fingers everywhere (a mug, a bowl): pinch the rim
        best = _rim_grasp(point, top, narrow, a, others)
    fdir, point = best[1], best[2]
    finger = d.down[:, FINGER_AXIS]
    yaw_now = np.arctan2(finger[1], finger[0])
    dyaw = (np.arctan2(fdir[1], fdir[0]) - yaw_now + np.pi / 2) % np.pi - np.pi / 2 + yaw_jitter
    return point, _rz(dyaw) @ d.down, height


def _grasp(d: _Driver, name: str, rng: np.random.Generator) -> Iterator[None]:
    """Pick ``name`` from above and lift it; up to ``GRASP_TRIES`` attempts (an attempt that leaves
    the object on the table opens, rises and aims again). Sets ``d.grasp`` = (grasp point, gripper
    rotation, lift height, lifted [m])."""
    lifted, safe_z = 0.0, d.scene["eef_pos"][2]
    for attempt in range(GRASP_TRIES):
        yaw, offset = float(rng.normal(0.0, 0.05)), rng.normal(0.0, 0.003, 2)
        # after a miss: the object's top at its body axis (a lid knob, a cap)
        high = attempt > 0 or name.startswith(HIGH_FIRST)
        point, grip_rot, _ = _grasp_frame(d, name, yaw, high)
        point[:2] += offset
        safe_z = max(point[2] + 0.12, d.scene["eef_pos"][2])
        above = point.copy()
        above[2] = safe_z
        yield from _move(d, above, grip_rot, OPEN, tol=0.015)
        # the object may have moved (settling, a neighbour's release): aim at where it is now
        point, grip_rot, _ = _grasp_frame(d, name, yaw, high)
        point[:2] += offset
        above = point.copy()
        above[2] = safe_z
        yield from _move(d, above, grip_rot, OPEN, tol=0.008, max_steps=20)
        yield from _descend(d, point, grip_rot, OPEN)
        yield from _hold(d, CLOSED, 12)
        z_grasp = d.scene["objects"][name]["pos"][2]
        lift = d.scene["eef_pos"].copy()
        lift[2] = safe_z + 0.05
        yield from _move(d, lift, grip_rot, CLOSED, tol=0.02)
        held = d.scene["objects"][name]
        lifted = float(held["pos"][2] - z_grasp)
        # where the hand holds the object: the object's box centre relative to the end effector
        center = held["pos"] + held["rot"] @ ((held["box_lo"] + held["box_hi"]) / 2.0)
        d.grasp = (point, grip_rot, lift[2], lifted, center - d.scene["eef_pos"])
        if lifted > 0.03 or d.done:
            return
        yield from _hold(d, OPEN, 6)


DOOR_MIN_REACH = 0.15
"""Least reach of a hinged part from its axis for it to be a door [m]: LIBERO-10's microwave door
reaches 0.267 m, the stove's knob (task 2, whose cook region is not behind anything) 0.071 m."""


def _door_front(sc: dict, target: str) -> np.ndarray | None:
    """Outward normal of the opening a hinged door closes (horizontal unit vector), for a region
    behind such a door (a microwave's heating region), else None: such a region is placed into
    through the opening (``_through_door``). A hinged part that reaches less than
    ``DOOR_MIN_REACH`` from its axis (a knob) is no door."""
    if not target.endswith("_region") or target not in sc["sites"]:
        return None
    try:
        j = sc["joints"][_joint_of(sc, target)]
    except NotImplementedError:
        return None
    if not j["hinge"]:
        return None
    axis = j["axis"] / np.linalg.norm(j["axis"])
    anchor = np.asarray(j["anchor"], float)
    far = np.array(
        [[x, y] for x in (j["part_lo"][0], j["part_hi"][0]) for y in (j["part_lo"][1], j["part_hi"][1])]
    )
    radial = np.c_[far - anchor[:2], np.zeros(len(far))]
    reach = np.linalg.norm(radial, axis=1)
    if reach.max() < DOOR_MIN_REACH:
        return None
    u = radial[int(np.argmax(reach))]
    u_closed = _rotation(axis, float(j["range"][1] - j["qpos"])) @ (u / np.linalg.norm(u))
    n = np.cross(axis, u_closed)
    n[2] = 0.0
    n /= np.linalg.norm(n)
    # the box's far corner includes the door's thickness (14 degrees off on the microwave): the
    # opening faces along the region's horizontal axis closest to this estimate
    frame = sc["sites"][target]["rot"]
    n = max((frame[:, 0], frame[:, 1]), key=lambda a: abs(a @ n)) * 1.0
    n[2] = 0.0
    n /= np.linalg.norm(n)
    return n if n @ (anchor - sc["sites"][target]["pos"]) > 0 else -n


def _pick_place(
    d: _Driver,
    name: str,
    target: str,
    rng: np.random.Generator,
    slot: tuple[int, int] = (0, 1),
    at: np.ndarray | None = None,
) -> Iterator[None]:
    """Pick ``name`` from above and release it on ``target`` (or on the table at the point ``at``)."""
    obj = d.scene["objects"][name]
    bottom = obj["pos"][2] + obj["box_lo"][2]
    yield from _grasp(d, name, rng)
    point, grip_rot, lift_z, lifted, held = d.grasp
    goal = _target_point(d.scene, target) if at is None else np.asarray(at, float)
    drop = goal.copy()
    drop[:2] -= held[:2]  # the object's centre, not the hand, over the target
    k, n = slot
    if n > 1 and target in d.scene["sites"]:  # several objects share a region: side by side
        site = d.scene["sites"][target]
        half = abs(float(site["size"][0]))
        u = site["rot"][:, 0]
        held_obj = d.scene["objects"][name]
        across = float(np.abs(u @ held_obj["rot"]) @ (held_obj["box_hi"] - held_obj["box_lo"]))
        # side by side with a gap, as long as the bodies stay inside the region
        spacing = max(min(2.0 * half / n, SLOT_SPACING), min(across + SLOT_GAP, 2.0 * (half - SLOT_GAP)))
        drop[:2] += (k - (n - 1) / 2.0) * spacing * u[:2]
    drawer = _slide_of(d.scene, target)
    if drawer is not None:  # an open drawer runs under its cabinet's face: release towards its front
        drop[:2] -= DRAWER_FRONT_SHIFT * drawer["axis"][:2]
    # release with the object's bottom a little above the target's top (the grasp point sat above the
    # object's bottom by the same amount as now below the gripper)
    drop[2] = goal[2] + (point[2] - bottom) + 0.03
    over = drop.copy()
    over[2] = max(drop[2] + 0.05, lift_z)
    yield from _move(d, over, grip_rot, CLOSED, tol=0.015)
    yield from _descend(d, drop, grip_rot, CLOSED)
    yield from _hold(d, OPEN, 10)
    up = d.scene["eef_pos"].copy()
    up[2] += 0.1
    yield from _move(d, up, grip_rot, OPEN, tol=0.02, max_steps=20)
    p = d.scene["objects"][name]["pos"]
    if at is not None:
        d.log.append(
            f"{name} -> {np.round(at, 3).tolist()}: lifted {lifted:.3f} m, left at {np.round(p, 3).tolist()}"
        )
        return
    where = "in the target box" if _inside(d.scene, target, p) else "outside the target box"
    d.log.append(f"{name} -> {target}: lifted {lifted:.3f} m, left at {np.round(p, 3).tolist()} ({where})")


def _pose(d: _Driver, pos, rot, grip, tol=0.01, rot_tol=0.05, max_steps=60, gain=1.0) -> Iterator[None]:
    """Like ``_move``, but until the orientation is reached as well (within ``rot_tol`` rad)."""
    pos = np.asarray(pos, float)
    for _ in range(max_steps):
        sc = d.scene
        if d.done or (
            np.linalg.norm(sc["eef_pos"] - pos) < tol
            and np.linalg.norm(_axis_angle(rot @ sc["eef_rot"].T)) < rot_tol
        ):
            return
        d.act(d.toward(pos, rot, grip, gain))
        yield


def _behind_hand(grip: np.ndarray, approach: np.ndarray, others: list[dict]) -> bool:
    """Whether a hand pointing horizontally along ``approach`` with its grip point at ``grip`` (and
    its forearm behind it, ``HAND_BACK`` along the approach, ``HAND_HALF`` each side) meets an
    object that rises above the hand's lower face: sampled on a grid of its footprint."""
    across = np.cross([0.0, 0.0, 1.0], approach)[:2]
    z_bottom = grip[2] - HAND_WIDTH / 2
    boxes = [b for b in (_world_box(o) for o in others) if b[1][2] > z_bottom]
    for t in np.linspace(0.02, HAND_BACK, 8):
        for w in np.linspace(-HAND_HALF, HAND_HALF, 9):
            q = grip[:2] - t * approach[:2] + w * across
            if any(np.all(q > lo[:2]) and np.all(q < hi[:2]) for lo, hi in boxes):
                return True
    return False


def _through_door(
    d: _Driver, name: str, target: str, front: np.ndarray, rng: np.random.Generator
) -> Iterator[None]:
    """Place ``name`` in a region behind a hinged door (a mug into a microwave, task 9): the hand,
    pointing through the opening with its fingers horizontal, pinches the object's part that faces
    the opening's outside (a mug's handle bar), lifts it over the cavity's floor, carries it in until
    its body is ``DOOR_DEPTH`` past the region's front or the hand meets the frame, lowers it, lets
    go and backs out. From above,
    the hand holding a mug's rim is higher than the opening (README)."""
    bar = d.env.far_box(name)
    obj = d.scene["objects"][name]
    if bar is None or (bar["pos"] - obj["pos"])[:2] @ front[:2] <= 0.0:
        d.log.append(f"{name} -> {target}: no part of it faces the opening's outside")
        return
    inward = -front

    def pointing(approach: np.ndarray) -> np.ndarray:
        """Fingers horizontal, approach axis ``approach``: of the two such hands the one nearer the
        current orientation."""
        best = None
        x = np.cross([0.0, 0.0, 1.0], approach)
        for sgn in (1.0, -1.0):
            rot = np.column_stack([sgn * x, np.cross(approach, sgn * x), approach])
            angle = float(np.linalg.norm(_axis_angle(rot @ d.scene["eef_rot"].T)))
            if best is None or angle < best[0]:
                best = (angle, rot)
        return best[1]

    site = d.scene["sites"][target]
    depth = float(np.abs(site["rot"][:2, :2] @ site["size"][:2]) @ np.abs(inward[:2]))
    others = [o for n, o in d.scene["objects"].items() if n != name]
    if _behind_hand(bar["pos"], inward, others):
        # the hand and forearm, horizontal behind the pinched part, would sweep a neighbour (the
        # other mug): set the object down in front of the opening first, from above
        stage = site["pos"] - (depth + STAGE_OFF) * inward
        stage[2] = obj["pos"][2] + obj["box_lo"][2]
        yield from _pick_place(d, name, target, rng, at=stage)
        bar = d.env.far_box(name)
        obj = d.scene["objects"][name]
        if bar is None or (bar["pos"] - obj["pos"])[:2] @ front[:2] <= 0.0:
            d.log.append(f"{name} -> {target}: set down turned, no part of it faces the opening's outside")
            return
    grasp = bar["pos"].copy()
    grasp[:2] += rng.normal(0.0, 0.002, 2)
    approach = inward
    rot = pointing(approach)
    back = grasp - approach * DOOR_APPROACH
    high = back.copy()
    high[2] = max(grasp[2] + 0.12, d.scene["eef_pos"][2])
    yield from _pose(d, high, rot, OPEN, tol=0.02, max_steps=80)
    yield from _pose(d, back, rot, OPEN, tol=0.01, max_steps=40)
    yield from _move(d, grasp, rot, OPEN, tol=0.006, gain=0.6, max_steps=40)
    yield from _hold(d, CLOSED, 12)
    rot = pointing(inward)  # straight through the opening from here on
    floor = float(site["pos"][2] - abs(site["size"][2]))
    held = d.scene["objects"][name]
    bottom = held["pos"][2] + held["box_lo"][2]
    lift = d.scene["eef_pos"] + np.array([0.0, 0.0, max(0.0, floor - bottom) + DOOR_CLEARANCE])
    yield from _pose(d, lift, rot, CLOSED, tol=0.01, max_steps=30)
    held = d.scene["objects"][name]
    lifted = float(held["pos"][2] + held["box_lo"][2] - bottom)
    grip_to_body = d.scene["eef_pos"] - held["pos"]
    # the body's position: the region's centre across the opening, DOOR_DEPTH past its front
    goal = site["pos"].copy()
    goal[:2] += (DOOR_DEPTH - depth) * inward[:2]
    inside = goal + grip_to_body
    inside[2] = d.scene["eef_pos"][2]
    before = inside + front * DOOR_APPROACH
    yield from _pose(d, before, rot, CLOSED, tol=0.01, max_steps=60)
    yield from _move(d, inside, rot, CLOSED, tol=0.004, gain=0.6, max_steps=60, stall=5)
    down = d.scene["eef_pos"] - np.array([0.0, 0.0, DOOR_CLEARANCE - 0.005])
    yield from _move(d, down, rot, CLOSED, tol=0.005, gain=0.5, max_steps=10)
    yield from _hold(d, OPEN, 10)
    out = d.scene["eef_pos"] + front * DOOR_APPROACH
    yield from _move(d, out, rot, OPEN, tol=0.02, max_steps=30)
    p = d.scene["objects"][name]["pos"]
    where = "in the target box" if _inside(d.scene, target, p) else "outside the target box"
    d.log.append(
        f"{name} -> {target} (through the door): lifted {lifted:.3f} m, left at "
        f"{np.round(p, 3).tolist()} ({where})"
    )


def _inside(sc: dict, target: str, p: np.ndarray) -> bool:
    """Whether a body position lies in a region site's ``in`` box (objects as targets: not judged)."""
    s = sc["sites"].get(target)
    return s is not None and bool(np.all(p > s["in_lb"]) and np.all(p < s["in_ub"]))


def _target_point(sc: dict, target: str) -> np.ndarray:
    """Top centre of a target: a region site (its box's top face) or an object (its box's top)."""
    if target in sc["sites"]:
        s = sc["sites"][target]
        p = s["pos"].copy()
        p[2] = s["pos"][2] - s["size"][2] if s["size"][2] > 0.02 else s["pos"][2]
        return p
    o = sc["objects"][target]
    p = o["pos"] + o["rot"] @ ((o["box_lo"] + o["box_hi"]) / 2.0)
    p[2] = o["pos"][2] + o["box_hi"][2]
    return p


def _joint_of(sc: dict, target: str) -> str:
    """The articulated joint a ``close``/``turnon`` predicate's argument refers to: the object's only
    joint, or for a region the joint of the same level (``white_cabinet_1_bottom_region`` ->
    ``white_cabinet_1_bottom_level``)."""
    names = list(sc["joints"])
    stem = target[: -len("_region")] if target.endswith("_region") else target
    for j in names:
        if j.startswith(stem):
            return j
    owner = [j for j in names if j.startswith(stem.rsplit("_", 1)[0])]
    if len(owner) == 1:
        return owner[0]
    raise NotImplementedError(f"no articulated joint for '{target}' among {names}")


def _slide_of(sc: dict, target: str) -> dict | None:
    """The slide joint (a drawer) a target region belongs to, or None."""
    if not target.endswith("_region"):
        return None
    try:
        j = sc["joints"][_joint_of(sc, target)]
    except NotImplementedError:
        return None
    return None if j["hinge"] else j


def _back_off(d: _Driver, rot: np.ndarray, push: np.ndarray, dist: float) -> Iterator[None]:
    """After a push: back away from the pushed part by ``dist`` against ``push`` and rise 10 cm."""
    back = d.scene["eef_pos"] - push * dist
    back[2] += 0.1
    yield from _move(d, back, rot, CLOSED, tol=0.02, max_steps=15)


def _log_close(d: _Driver, name: str, q0: float, kind: str) -> None:
    j = d.scene["joints"][name]
    d.log.append(
        f"close {name}{kind}: q {q0:.3f} -> {j['qpos']:.3f} (range {np.round(j['range'], 3).tolist()})"
    )


def _close_slide(d: _Driver, target: str) -> Iterator[None]:
    """Push a drawer shut: fingers closed, lowered in front of its face, pushed along the slide to the
    closed end of its range (LIBERO's cabinets close towards the top of the range)."""
    name = _joint_of(d.scene, target)
    q0 = d.scene["joints"][name]["qpos"]
    # the hand's thin side leads: its long axis (along the fingers) across the push
    ax = d.scene["joints"][name]["axis"]
    finger = d.down[:, FINGER_AXIS]
    dyaw = (np.arctan2(ax[0], -ax[1]) - np.arctan2(finger[1], finger[0]) + np.pi / 2) % np.pi - np.pi / 2
    rot = _rz(dyaw) @ d.down
    # fingers tilted towards the push: the forearm stays clear of the cabinet's face
    tilt = np.cross(ax / np.linalg.norm(ax), [0.0, 0.0, 1.0])
    rot = _rotation(tilt / max(1e-9, np.linalg.norm(tilt)), PUSH_TILT) @ rot
    for _ in range(PUSH_TRIES):
        j = d.scene["joints"][name]
        travel = float(j["range"][1] - j["qpos"])
        if travel <= 0.003 or d.done:
            break
        axis = j["axis"] / np.linalg.norm(j["axis"])
        lo, hi = j["part_lo"], j["part_hi"]
        center = (lo + hi) / 2.0
        half = float(np.abs(axis) @ ((hi - lo) / 2.0))
        start = center - axis * (half + PUSH_GAP)
        start[2] = lo[2] + 0.6 * (hi[2] - lo[2])
        above = start.copy()
        above[2] = max(hi[2] + 0.08, d.scene["eef_pos"][2])
        yield from _move(d, above, rot, CLOSED, tol=0.015)
        yield from _descend(d, start, rot, CLOSED)
        end = start + axis * (travel + PUSH_GAP + 0.01)
        yield from _move(d, end, rot, CLOSED, tol=0.01, gain=0.5, max_steps=80)
        yield from _back_off(d, rot, axis, 0.03)
    _log_close(d, name, q0, "")


def _leaf(sc: dict, target: str, name: str) -> tuple[np.ndarray, float, float]:
    """(closed direction, reach [m], thickness on the outer side [m]) of the hinged door ``name``
    of object ``target``: the direction from the hinge along the door when closed, snapped to the
    object's nearest horizontal axis (the door's bounding box alone is off by its thickness: 14
    degrees on the microwave), how far the door reaches, and how far its outer face (with any
    handle) stands off the hinge line, towards which the door swings open."""
    j = sc["joints"][name]
    axis = j["axis"] / np.linalg.norm(j["axis"])
    anchor = np.asarray(j["anchor"], float)
    radial = np.asarray(j["part_corners"], float) - anchor
    radial -= np.outer(radial @ axis, axis)
    reach = float(np.linalg.norm(radial, axis=1).max())
    far = radial[int(np.argmax(np.linalg.norm(radial, axis=1)))]
    closed = _rotation(axis, float(j["range"][1] - j["qpos"])) @ (far / reach)
    frame = sc["objects"][target]["rot"] if target in sc["objects"] else np.eye(3)
    snapped = max((frame[:, 0], -frame[:, 0], frame[:, 1], -frame[:, 1]), key=lambda a: float(a @ closed))
    u_now = _rotation(axis, float(j["qpos"] - j["range"][1])) @ snapped
    t = np.cross(axis, u_now)  # where the door's points go as it closes
    thick = float(max(0.0, -(radial @ t).min()))
    return snapped, reach, thick


def _close_hinge(d: _Driver, target: str) -> Iterator[None]:
    """Swing a hinged door shut: fingers closed and pointing down, the hand's thin side towards the
    door, lowered off its outer face at ``HINGE_PUSH_AT`` of its reach, then carried along the arc
    that point follows towards the closed end of the range (LIBERO's microwave closes at 0),
    ``HINGE_STEP`` a way point, the hand turning with the door, a little past closed so it seats."""
    name = _joint_of(d.scene, target)
    j = d.scene["joints"][name]
    q0 = float(j["qpos"])
    axis = j["axis"] / np.linalg.norm(j["axis"])
    anchor = np.asarray(j["anchor"], float)
    u_closed, reach, thick = _leaf(d.scene, target, name)
    z = float(j["part_lo"][2] + 0.5 * (j["part_hi"][2] - j["part_lo"][2]))
    off = thick + HAND_WIDTH / 2 + HINGE_GAP  # the hand's centre off the hinge line
    finger = d.down[:, FINGER_AXIS]
    q_closed = float(j["range"][1])
    turn = float(np.sign(axis[2]) or 1.0)
    for _ in range(PUSH_TRIES):
        q = float(d.scene["joints"][name]["qpos"])
        remaining = q_closed - q
        if remaining <= 0.02 or d.done:
            break

        u_now = _rotation(axis, q - q_closed) @ u_closed
        # the hand's long side (along the fingers) along the door: the nearer of the two ways now,
        # then turning with the door (continuously: no half turn where the nearer way changes)
        yaw0 = (
            np.arctan2(u_now[1], u_now[0]) - np.arctan2(finger[1], finger[0]) + np.pi / 2
        ) % np.pi - np.pi / 2

        def point(
            theta: float, q: float = q, yaw0: float = yaw0
        ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
            u = _rotation(axis, q - q_closed + theta) @ u_closed
            t = np.cross(axis, u)
            p = anchor + HINGE_PUSH_AT * reach * u - off * t
            p[2] = z
            return p, t, _rz(yaw0 + turn * theta) @ d.down

        start, t, rot = point(0.0)
        above = start.copy()
        above[2] = max(float(j["part_hi"][2]) + 0.04, d.scene["eef_pos"][2])
        if d.scene["eef_pos"][2] < above[2] - 0.02:  # up first: over the door, never through it
            up = d.scene["eef_pos"].copy()
            up[2] = above[2]
            yield from _move(d, up, rot, CLOSED, tol=0.02, max_steps=20)
        yield from _pose(d, above, rot, CLOSED, tol=0.015, rot_tol=0.1)
        yield from _descend(d, start, rot, CLOSED)
        for theta in np.arange(HINGE_STEP, remaining + HINGE_PAST, HINGE_STEP):
            p, t, rot = point(float(theta))
            # past closed the door stops the hand: a short press each
            steps = 25 if theta < remaining + HINGE_STEP else 8
            yield from _pose(d, p, rot, CLOSED, tol=0.015, rot_tol=0.1, gain=0.7, max_steps=steps)
        yield from _back_off(d, rot, t, 0.05)
    _log_close(d, name, q0, " (hinge)")


def supported(scene: dict) -> bool:
    """Whether every predicate of the scene's goal has a skill: ``in``/``on``, ``close`` for drawers
    (slides) and hinged doors, ``turnon`` for hinged knobs."""
    for p in scene["goal"]:
        if p[0] == "close":
            try:
                _joint_of(scene, p[1])
            except NotImplementedError:
                return False
        elif p[0] == "turnon":
            try:
                if not scene["joints"][_joint_of(scene, p[1])]["hinge"]:
                    return False
            except NotImplementedError:
                return False
        elif p[0] not in ("in", "on"):
            return False
    return True


def _turn_on(d: _Driver, target: str) -> Iterator[None]:
    """Turn a stove's knob on: pinch its bar across the narrower side, then turn the hand about the
    knob's axis (positions on the arc, the hand's yaw with it) to ``KNOB_TURN`` past the current
    angle; LIBERO's stoves are on from 0.5 rad."""
    name = _joint_of(d.scene, target)
    j = d.scene["joints"][name]
    q0 = j["qpos"]
    h = j["handle"]
    narrow_i = 0 if h["half"][0] <= h["half"][1] else 1
    narrow = h["rot"][:, narrow_i]
    finger = d.down[:, FINGER_AXIS]
    dyaw = (
        np.arctan2(narrow[1], narrow[0]) - np.arctan2(finger[1], finger[0]) + np.pi / 2
    ) % np.pi - np.pi / 2
    rot0 = _rz(dyaw) @ d.down
    top = h["pos"][2] + float(np.abs(h["rot"][2]) @ h["half"])
    point = h["pos"].copy()
    point[2] = top - KNOB_DEPTH
    above = point.copy()
    above[2] = max(top + 0.08, d.scene["eef_pos"][2])
    yield from _move(d, above, rot0, OPEN, tol=0.01)
    yield from _descend(d, point, rot0, OPEN)
    yield from _hold(d, CLOSED, 10)
    axis_pt = j["anchor"]
    grip = d.scene["eef_pos"].copy()
    sign = 1.0 if j["axis"][2] >= 0 else -1.0
    for k in range(1, KNOB_STEPS + 1):
        phi = sign * KNOB_TURN * k / KNOB_STEPS
        r = _rz(phi)
        pos = axis_pt + r @ (grip - axis_pt)
        for _ in range(3):
            if d.done:
                return
            d.act(d.toward(pos, r @ rot0, CLOSED))
            yield
    yield from _hold(d, OPEN, 6)
    up = d.scene["eef_pos"].copy()
    up[2] += 0.08
    yield from _move(d, up, d.scene["eef_rot"], OPEN, tol=0.02, max_steps=15)
    q = d.scene["joints"][name]["qpos"]
    d.log.append(f"turn on {name}: q {q0:.3f} -> {q:.3f}")


_ORDER = {"in": 0, "on": 0, "turnon": 1, "close": 2}
"""Skills run in this order: objects go into a drawer before it is closed."""


def _skills(d: _Driver, rng: np.random.Generator) -> Iterator[None]:
    goal = sorted(d.scene["goal"], key=lambda p: _ORDER.get(p[0], 9))
    targets = [p[2] for p in goal if p[0] in ("in", "on")]
    placed: dict[str, int] = {}
    for pred in goal:
        kind = pred[0]
        if kind in ("in", "on") and _door_front(d.scene, pred[2]) is not None:
            yield from _through_door(d, pred[1], pred[2], _door_front(d.scene, pred[2]), rng)
        elif kind in ("in", "on"):
            k = placed.get(pred[2], 0)
            placed[pred[2]] = k + 1
            yield from _pick_place(d, pred[1], pred[2], rng, (k, targets.count(pred[2])))
        elif kind == "close" and not d.scene["joints"][_joint_of(d.scene, pred[1])]["hinge"]:
            yield from _close_slide(d, pred[1])
        elif kind == "close":
            yield from _close_hinge(d, pred[1])
        elif kind == "turnon":
            yield from _turn_on(d, pred[1])
        else:
            raise NotImplementedError(f"no expert skill for predicate {pred}")


def _settle(d: _Driver, max_steps: int = 40) -> None:
    """Hold still until no object moves by 1 mm in a step: LIBERO's official initial states leave
    objects slightly interpenetrating, and some pop up to a metre high before they come to rest."""
    before = {n: o["pos"].copy() for n, o in d.scene["objects"].items()}
    for _ in _hold(d, OPEN, max_steps):
        now = {n: o["pos"].copy() for n, o in d.scene["objects"].items()}
        if max(float(np.linalg.norm(now[n] - before[n])) for n in now) < 0.001:
            return
        before = now


def run_expert(
    env: LiberoEnv,
    init_index: int,
    rng: np.random.Generator,
    *,
    record: bool = False,
    noise: float = 0.0,
    view_every: int = 1,
) -> ExpertResult:
    """One demonstration from the official initial state ``init_index`` (``env`` started); with
    ``record`` the MuJoCo state and the policy's state observation of every step are kept, and the
    two views when ``env`` renders. ``noise`` > 0 adds N(0, noise) to the six motion components of
    every executed action (action units) while the expert's own action is kept as the label (DART):
    the expert corrects the drift, so the data covers states a drifting policy visits. ``view_every``
    K > 1 records the views of frames 0, K, 2K, ... only (the other steps are not rendered)."""
    first = env.reset(init_index)
    task = env.start()
    kicks = np.random.default_rng(rng.integers(2**63)) if noise > 0.0 else None  # rng untouched without noise
    d = _Driver(env, task.max_steps, first, record, noise, kicks, view_every)
    _settle(d)
    for _ in _skills(d, rng):
        if d.done:
            break
    for _ in _hold(d, OPEN, SETTLE_STEPS):  # objects released last may need a moment to come to rest
        pass
    return ExpertResult(
        d.success,
        len(d.actions),
        np.asarray(d.actions).reshape(-1, 7),
        tuple(d.log),
        np.asarray(d.sim_states) if record else None,
        np.asarray(d.observations) if record else None,
        {v: np.asarray(f, dtype=np.uint8) for v, f in d.views.items()} or None,
        np.asarray(d.executed).reshape(-1, 7) if noise > 0.0 else None,
        np.asarray(d.view_frames, dtype=np.int64) if d.views else None,
    )
