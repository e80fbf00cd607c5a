"""Entry point: ``solve(client, instruction)`` parses the instruction into steps and runs the skills.

Understood phrases (one instruction may chain several with commas, "and", "then"):

- ``put/take the <object> [from the counter | out of the open drawer] into the open drawer | on the
  plate | on the counter | into the sink``: pick and place;
- ``close the (open) drawer``, ``open the drawer``;
- ``close the cabinet (door)``;
- ``turn on/off the <front|rear> <left|right> burner``;
- ``move the cup from the sink onto the <front|rear> <left|right> burner [and turn that burner on]`` and
  ``move the cup from the sink to the dish rack`` (``cups``).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any

import numpy as np

from .articulation import close_door, push_drawer_holding
from .cups import burner_centre, cup_from_sink, cup_to_burner, cup_to_rack, rack_spot
from .dishes import (
    bowl_to_sink,
    empty_bowl,
    find_bowl,
    grasp_rim,
    sink_basin,
)
from .fixtures import find_open_door
from .kitchen import BESIDE_Y, COUNTER_Z, EMPTY, FRONT_Y, SIDE_GAP, STAND_Y, Drawer
from .knobs import turn_knob
from .skills import Skills

__all__ = ["Step", "parse", "solve"]

SINK_DROP = 0.03
"""Height of an object's bottom above the counter tops when let go over the sink basin [m]."""
PLACE_REACH = 0.45
"""Least distance ahead of the base's centre of a place position [m] (nearer, the arm cannot reach down)."""
CARRY_Z = 1.1
"""Tool height while carrying an object over the counters [m] (below the wall cabinets, 1.45 m up)."""
OBJECTS = ("apple", "orange", "lemon", "bread", "butter", "can", "cup", "milk", "bottle", "bowl")
"""Object categories an instruction may name."""


@dataclass(frozen=True)
class Step:
    """One step of a plan: ``kind`` (``pick_place``, ``close_drawer``, ``open_drawer``, ``close_door``,
    ``knob``), the object, where from and to, and for a knob the burner words and on/off."""

    kind: str
    obj: str = ""
    source: str = ""
    dest: str = ""
    burner: str = ""
    on: bool = True


def parse(instruction: str) -> list[Step]:
    """The steps of an instruction, in a workable order: an open hinged door first (it stands 0.5 m out
    of the run, in the way), then the object (before closing the drawer it fills), knobs last."""
    text = instruction.lower()
    steps: list[Step] = []
    if re.search(r"\bdump\b", text) and "bowl" in text:
        return [Step("dump", "bowl", "counter", "sink" if "sink" in text else "counter")]
    obj = next((w for w in re.findall(r"[a-z]+", text) if w in OBJECTS), "")
    if obj and re.search(r"\b(put|take|move|place)\b", text):
        source = "drawer" if re.search(r"(out of|from) the (open )?drawer", text) else "counter"
        if "sink" in text and re.search(r"(out of|from) the sink", text):
            source = "sink"
        dest = "counter"
        for word, key in (
            ("drawer", "drawer"),
            ("plate", "plate"),
            ("sink", "sink"),
            ("(dish )?rack", "rack"),
        ):
            if re.search(rf"(into|in|on|onto|to) the (open )?{word}", text) and key != source:
                dest = key
                break
        on_burner = re.search(r"(onto|on) the (front|rear) (left|right) burner", text)
        if on_burner:
            dest = "burner"
        burner = f"{on_burner.group(2)} {on_burner.group(3)}" if on_burner else ""
        steps.append(Step("pick_place", obj, source, dest, burner=burner))
        if on_burner and re.search(r"turn (that|the) burner on|turn on (that|the) burner", text):
            steps.append(Step("knob", burner=burner, on=True))
    if re.search(r"close the (open )?drawer", text):
        steps.append(Step("close_drawer"))
    if re.search(r"\bopen the drawer", text):
        steps.append(Step("open_drawer"))
    if re.search(r"close the cabinet", text):
        steps.insert(0, Step("close_door"))
    for m in re.finditer(r"turn (on|off) the (front|rear) (left|right)", text):
        steps.append(Step("knob", burner=f"{m.group(2)} {m.group(3)}", on=m.group(1) == "on"))
    return steps


def solve(client: Any, instruction: str) -> str:
    """Reset the session once, then carry out the instruction; returns the skill log (one line per
    event) for the caller to read."""
    sk = Skills(client)
    sk.reset()
    steps = parse(instruction)
    sk.note(f"plan: {steps}")
    ctx: dict[str, Any] = {"close_drawer": any(s.kind == "close_drawer" for s in steps)}
    for step in steps:
        try:
            ok = RUN[step.kind](sk, step, ctx)
        except Exception as exc:  # a skill's bug must not end the attempt: try the next step
            ok = False
            sk.note(f"{step.kind} raised {exc!r}")
        sk.note(f"{step.kind}: {'ok' if ok else 'failed'}; success {sk.robot.observe()['success']}")
        if sk.obs["success"]:
            break
    return "\n".join(sk.log)


# -- step runners ---------------------------------------------------------------------------------


def _drawer(sk: Skills, ctx: dict[str, Any]) -> Drawer | None:
    if ctx.get("drawer") is None:
        ctx["drawer"] = sk.find_open_drawer()
    return ctx["drawer"]


def _beside(sk: Skills, d: Drawer, target_x: float) -> tuple[float, float, float]:
    """(x, y [m], side) of the base beside the open drawer, on the side of ``target_x`` (+1: +x) unless
    the fridge stands there (its front is 0.1 m prouder and the arm would hit it)."""
    side = 1.0 if target_x >= d.x else -1.0
    fridge = sk.extent_x("fridge", (-np.inf, -np.inf, 0.95), (np.inf, np.inf, 2.0))
    for s in (side, -side):
        x = d.x + s * (d.width / 2 + SIDE_GAP)
        if fridge is None or not (fridge[0] - 0.3 < x < fridge[1] + 0.3):
            return x, BESIDE_Y, s
    return d.x + side * (d.width / 2 + SIDE_GAP), BESIDE_Y, side


def _find_on_top(sk: Skills, prompt: str, radius: float = 0.08) -> np.ndarray | None:
    """(x, y, top z) [m] of an object standing on a counter top, or None."""
    pts = sk.search(prompt, (-np.inf, -np.inf, 0.88), (np.inf, 0.0, 1.3), radius=radius)
    if len(pts) < 3:
        return None
    mid = (
        (pts[:, :2].min(axis=0) + pts[:, :2].max(axis=0)) / 2
        if radius > 0.1
        else np.median(pts[:, :2], axis=0)
    )
    return np.array([*mid, np.percentile(pts[:, 2], 95)])


def _find_near(sk: Skills, prompt: str, fixture: str) -> np.ndarray | None:
    """``_find_on_top`` again from in front of ``fixture`` (the object stands near it, out of sight)."""
    pts = sk.search(fixture, (-np.inf, -np.inf, 0.6), (np.inf, 0.0, 1.2), radius=None)
    if len(pts) < 10:
        sk.note(f"no {fixture} in sight")
        return None
    sk.tuck()
    sk.goto(float(np.median(pts[:, 0])), STAND_Y)
    return _find_on_top(sk, prompt)


def _find_in_drawer(sk: Skills, prompt: str, d: Drawer) -> np.ndarray | None:
    """(x, y, top z) [m] of an object on the open drawer's tray, or None."""
    lo = (d.x - d.width / 2, d.front_y, d.floor_z - 0.02)
    hi = (d.x + d.width / 2, FRONT_Y, d.floor_z + 0.2)
    pts = sk.find(prompt, lo, hi)
    if len(pts) < 3:
        return None
    return np.array([*np.median(pts[:, :2], axis=0), np.percentile(pts[:, 2], 95)])


def run_pick_place(sk: Skills, step: Step, ctx: dict[str, Any]) -> bool:
    d = _drawer(sk, ctx) if "drawer" in (step.source, step.dest) else None
    if step.source == "sink":
        start = np.asarray(sk.obs["base_pos"][:2], float).copy()  # the robot starts in front of the sink
        # Where it goes first (it stands near the sink), then back to the sink for the cup.
        if step.dest == "burner":
            centre = burner_centre(sk, step.burner)
        elif step.dest == "rack":
            centre = rack_spot(sk)
        else:
            sk.note(f"no destination for {step.dest}")
            return False
        if centre is None:
            sk.note(f"no {step.dest} in sight")
            return False
        sk.note(f"{step.dest} at {np.round(centre, 3)}")
        sk.tuck()
        sk.goto(float(start[0]), float(start[1]))
        held = cup_from_sink(sk, step.obj)
        if held is None:
            return False
        if step.dest == "burner":
            return cup_to_burner(sk, held, centre)
        return cup_to_rack(sk, held, centre)
    if step.source == "drawer":
        guess = _find_in_drawer(sk, step.obj, d) if d is not None else None
    else:
        guess = _find_on_top(sk, step.obj)
        if guess is None and step.dest in ("sink", "rack"):
            guess = _find_near(sk, step.obj, "sink" if step.dest == "sink" else "dish rack")
    if guess is None:
        sk.note(f"cannot find the {step.obj}")
        return False
    sk.note(f"{step.obj} near {np.round(guess, 3)}")
    plate = _find_on_top(sk, "plate", radius=0.14) if step.dest == "plate" else None
    if plate is not None:
        sk.note(f"plate near {np.round(plate, 3)}")
    # where to stand for the grasp
    if step.source == "drawer" and d is not None:
        sk.goto(d.x, min(float(guess[1]) - 0.5, STAND_Y + 0.05))
    elif d is not None:
        x, y, side = _beside(sk, d, guess[0])
        ctx["side"] = side
        sk.goto(x, y)
    else:
        sk.goto(float(guess[0]), BESIDE_Y)
    held = sk.pick(step.obj, guess)
    if held is None:
        return False
    if step.dest == "drawer" and d is not None:
        side = ctx.get("side", 1.0)
        # Near the counter's edge: a round fruit lags 5/7 of the tray's travel as it rolls while the drawer
        # closes; from here it ends inside, not against the drawer's front.
        xy = np.array([d.x + side * min(0.06, d.width / 2 - 0.12), FRONT_Y - 0.075])
        sk.place(held, xy, d.floor_z, carry_z=min(max(sk.obs["ee_pos"][2], 1.05), 1.2))
        return True
    if step.dest == "plate" and plate is not None:
        if d is not None and step.source == "drawer" and ctx.get("close_drawer"):
            # Close the drawer first, the object still in the hand, and put it on the plate last: a fruit
            # left on a plate rolls off within seconds at any disturbance.
            side = 1.0 if plate[0] >= d.x else -1.0
            ctx["drawer_closed"] = push_drawer_holding(sk, d, held, side)
            if sk.obs["gripper"] <= EMPTY:
                sk.note(f"lost the {step.obj} while pushing the drawer")
                return False
            if ctx["drawer_closed"]:
                sk.goto(float(plate[0]), min(BESIDE_Y, float(plate[1]) - PLACE_REACH))
        if d is not None and step.source == "drawer" and not ctx.get("drawer_closed"):
            sk.carry_pose()
            x, y, _ = _beside(sk, d, plate[0])
            sk.goto(x, float(sk.obs["base_pos"][1]), lane=False)  # sideways in front of the drawer: the deck
            sk.goto(x, y, lane=False)  # passes under it
        elif abs(plate[0] - sk.obs["base_pos"][0]) > 0.45:
            sk.carry_pose()
            sk.goto(float(plate[0]), BESIDE_Y)
        sk.place(held, plate[:2], plate[2], drop=0.02, carry_z=min(max(sk.obs["ee_pos"][2], 1.1), 1.2))
        return True
    if step.dest == "sink":
        sk.carry_pose()
        basin = sk.find("sink basin", (-np.inf, -np.inf, 0.6), (np.inf, 0.0, 0.95), radius=None)
        if len(basin) >= 10:
            mid = (np.percentile(basin[:, :2], 5, axis=0) + np.percentile(basin[:, :2], 95, axis=0)) / 2
            floor = float(np.percentile(basin[:, 2], 3))
            sk.note(f"sink basin at {np.round(mid, 3)}, floor {floor:.2f}")
            sk.carry_pose()  # from the look pose (1.6 m up): carried that high the hand hits the wall cabinets
            sk.goto(float(mid[0]), BESIDE_Y)
            # Let go just above the counter top's height over the basin's middle: the object drops in (a low
            # release far out over the basin is beyond the arm's reach).
            sk.place(held, mid, COUNTER_Z, drop=SINK_DROP, carry_z=CARRY_Z)
            return True
    sk.note(f"no destination for {step.dest}")
    return False


def run_dump(sk: Skills, step: Step, ctx: dict[str, Any]) -> bool:
    """Find the bowl and the sink, take what lies in the bowl out onto the counter (away from the sink),
    then grip the bowl's rim and put it into the sink (with what could not be taken out)."""
    guess = _find_on_top(sk, "bowl", radius=0.14)
    if guess is None:
        sk.note("cannot find the bowl")
        return False
    basin = sink_basin(sk)
    if basin is None:
        sk.note("no sink basin in sight")
        return False
    sk.note(f"bowl near {np.round(guess, 3)}, sink basin at {np.round(basin[0], 3)}")
    sk.goto(float(guess[0]), BESIDE_Y)
    bowl = find_bowl(sk, guess)
    if bowl is None:
        return False
    lateral = np.array([-np.sin(sk.obs["base_yaw"]), np.cos(sk.obs["base_yaw"])])
    away = -lateral if (basin[0] - bowl.center) @ lateral > 0 else lateral
    prompts = tuple(o for o in OBJECTS if o != "bowl")
    empty_bowl(sk, bowl, prompts, away)
    sk.tuck()
    sk.goto(float(bowl.center[0]), BESIDE_Y)
    bowl = find_bowl(sk, np.array([*bowl.center, bowl.rim_z])) or bowl  # it may have moved a little
    got = grasp_rim(sk, bowl)
    if got is None:
        return False
    held, u = got
    bowl_to_sink(sk, held, bowl, u, basin, BESIDE_Y)
    return True


def run_close_drawer(sk: Skills, step: Step, ctx: dict[str, Any]) -> bool:
    if ctx.get("drawer_closed"):
        return True
    d = _drawer(sk, ctx)
    if d is None:
        sk.note("no open drawer seen")
        return False
    sk.tuck()
    sk.push_drawer(d)
    return True


def run_open_drawer(sk: Skills, step: Step, ctx: dict[str, Any]) -> bool:
    return False


def run_close_door(sk: Skills, step: Step, ctx: dict[str, Any]) -> bool:
    door = find_open_door(sk)
    return door is not None and close_door(sk, door)


def run_knob(sk: Skills, step: Step, ctx: dict[str, Any]) -> bool:
    return turn_knob(sk, step.burner, step.on)


RUN = {
    "pick_place": run_pick_place,
    "dump": run_dump,
    "close_drawer": run_close_drawer,
    "open_drawer": run_open_drawer,
    "close_door": run_close_door,
    "knob": run_knob,
}
_ = COUNTER_Z
