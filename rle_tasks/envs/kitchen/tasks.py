"""The atomic kitchen tasks: initial-state samplers and success conditions, RoboCasa's semantics.

A task samples an ``Episode`` for a kitchen (which fixture and object are the target, the initial
joint states, the objects and where the robot stands) and states its success as a conjunction of
named ``Condition``s over the compiled scene; ``success`` is all of them. The stage report (family
02) reads every condition.

| task | start | success (RoboCasa) |
|---|---|---|
| ``OpenFridge`` | fridge door closed | every door joint of the fridge >= 0.90 open |
| ``CloseCabinet`` | a hinged base cabinet's door 0.90-1.00 open | its door <= 0.005 open |
| ``TurnOnStove`` | every knob off; one burner named | that burner's knob wrapped angle in [0.35, 2 pi - 0.35] |
| ``PickPlaceCounterToDrawer`` | a drawer fully open; the object on the counter beside it | object inside the drawer, touching no counter top, gripper far |
| ``PickPlaceMicrowaveToCounter`` | microwave door open; the object on its plate; a plate on the counter | object in the counter plate, gripper far |

The robot starts in front of the target fixture, facing it, with a seeded offset; spawn and object
placement work in the fixture's own frame (``placement``), so every layout kind is served.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import mujoco
import numpy as np

from rle_tasks.envs.kitchen import predicates as pr
from rle_tasks.envs.kitchen.fixture import BURNERS, Fixture
from rle_tasks.envs.kitchen.objects import extent, graspable
from rle_tasks.envs.kitchen.placement import (
    FLAT_KINDS,
    STANDOFF,
    along,
    host_of,
    nearest_flat,
    neighbours,
    same_run,
    spawn,
    spot_near,
    straighten,
    unstraighten,
)

__all__ = ["FLAT_KINDS", "STANDOFF", "TASKS", "Condition", "Episode", "KitchenTask", "Placement", "spot_near"]


@dataclass(frozen=True)
class Placement:
    """An object of the episode.

    Attributes:
        name: Body name.
        category: Object category.
        pos: World position of its lowest point [m]; with ``inside``, (u, v, 0): fractions in
            [-0.5, 0.5] of the fixture interior's width and depth; with ``on``, (u, v, 0): fractions of
            the container's radius.
        yaw: Heading about the world z [rad].
        inside: Fixture whose interior floor holds the object (placed after the joints are set).
        on: Object (placed earlier) the object rests in or on.
    """

    name: str
    category: str
    pos: tuple[float, float, float]
    yaw: float = 0.0
    inside: str | None = None
    on: str | None = None


@dataclass(frozen=True)
class Episode:
    """One sampled initial state of a task in a kitchen.

    Attributes:
        task: Task name.
        instruction: The language instruction.
        robot: Base pose at spawn: x, y [m], heading [rad] (``yaw`` + pi/2 faces a fixture of yaw ``yaw``).
        joints: Initial state of articulated joints as a fraction of their range (others closed).
        objects: Objects to place.
        target: Roles -> names (``fixture``, ``object``, ``container``, ``burner``, ``knob``).
    """

    task: str
    instruction: str
    robot: tuple[float, float, float]
    joints: tuple[tuple[str, float], ...] = ()
    objects: tuple[Placement, ...] = ()
    target: dict[str, str] = field(default_factory=dict)


@dataclass(frozen=True)
class Condition:
    """A named predicate of the scene state (``fn(model, data) -> bool``)."""

    name: str
    fn: Callable[[mujoco.MjModel, mujoco.MjData], bool]


def _tops(fixtures: dict[str, Fixture]) -> tuple[str, ...]:
    """Counter-top geoms of every fixture (objects must not touch them to count as inside)."""
    return tuple(
        g for f in fixtures.values() if f.kind not in ("microwave", "dish_rack") for g in f.top_geoms
    )


class KitchenTask:
    """Base of the atomic tasks: ``sample`` an episode, ``conditions`` of success."""

    name: str = ""
    description: str = ""

    def sample(self, fixtures: dict[str, Fixture], rng: np.random.Generator) -> Episode:
        raise NotImplementedError

    def conditions(self, episode: Episode, fixtures: dict[str, Fixture], names) -> tuple[Condition, ...]:
        raise NotImplementedError


class OpenFridge(KitchenTask):
    name = "OpenFridge"
    description = "open the refrigerator door"

    def sample(self, fixtures, rng):
        f = fixtures["fridge"]
        hinge_left = f.hinge_left
        side = 1.0 if hinge_left else -1.0
        robot = spawn(rng, f, dx=side * (f.size[0] / 2 + 0.05))
        return Episode(self.name, "Open the refrigerator door.", robot, target={"fixture": f.name})

    def conditions(self, episode, fixtures, names):
        f = fixtures[episode.target["fixture"]]
        return (Condition("fridge door open", lambda m, d: pr.is_open(m, d, f)),)


class CloseCabinet(KitchenTask):
    name = "CloseCabinet"
    description = "close the cabinet door"

    def sample(self, fixtures, rng):
        cabs = sorted(n for n, f in fixtures.items() if f.kind == "hinge_cabinet")
        f = fixtures[cabs[int(rng.integers(len(cabs)))]]
        side = -1.0 if f.hinge_left else 1.0
        robot = spawn(rng, f, dx=side * (f.size[0] / 2 + 0.3), standoff=STANDOFF + 0.05)
        q = float(rng.uniform(0.9, 1.0))
        return Episode(
            self.name,
            "Close the cabinet door.",
            robot,
            joints=((f.joints[0], q),),
            target={"fixture": f.name},
        )

    def conditions(self, episode, fixtures, names):
        f = fixtures[episode.target["fixture"]]
        return (Condition("cabinet door closed", lambda m, d: pr.is_closed(m, d, f)),)


class TurnOnStove(KitchenTask):
    name = "TurnOnStove"
    description = "turn on the specified burner"

    def sample(self, fixtures, rng):
        f = fixtures["stove"]
        burner = BURNERS[int(rng.integers(len(BURNERS)))]
        words = burner.replace("_", " ")
        return Episode(
            self.name,
            f"Turn on the {words} burner of the stove.",
            spawn(rng, f),
            target={"fixture": f.name, "burner": burner, "knob": f.burners[burner][0]},
        )

    def conditions(self, episode, fixtures, names):
        knob = episode.target["knob"]
        return (
            Condition(
                f"{episode.target['burner'].replace('_', ' ')} burner on", lambda m, d: pr.knob_on(m, d, knob)
            ),
        )


class PickPlaceCounterToDrawer(KitchenTask):
    name = "PickPlaceCounterToDrawer"
    description = "move the target into the drawer"

    def sample(self, fixtures, rng):
        drawers = sorted(n for n, f in fixtures.items() if f.kind == "drawer_cabinet")
        f = fixtures[drawers[int(rng.integers(len(drawers)))]]
        cats = [c for c in graspable() if extent(c)[1][2] <= 0.05]
        cat = cats[int(rng.integers(len(cats)))]
        pos = spot_near(fixtures, f, rng, cat)
        return Episode(
            self.name,
            f"Pick the {cat} from the counter and place it in the drawer.",
            spawn(rng, f, standoff=STANDOFF + 0.1),
            joints=((f.joints[0], 1.0),),
            objects=(Placement("obj", cat, pos, float(rng.uniform(-math.pi, math.pi))),),
            target={"fixture": f.name, "object": "obj"},
        )

    def conditions(self, episode, fixtures, names):
        f = fixtures[episode.target["fixture"]]
        cat = episode.objects[0].category
        tops = _tops(fixtures)
        return (
            Condition(f"{cat} inside the drawer", lambda m, d: pr.inside(m, d, "obj", cat, f.interior)),
            Condition(
                f"{cat} off the counter",
                lambda m, d: not pr.bodies_touch(m, d, "obj", {m.geom(g).id for g in tops}),
            ),
            Condition(
                "gripper far from the object", lambda m, d: pr.gripper_far(m, d, "obj", names.finger_pads)
            ),
        )


class PickPlaceMicrowaveToCounter(KitchenTask):
    name = "PickPlaceMicrowaveToCounter"
    description = "move the target to its counter destination"

    def sample(self, fixtures, rng):
        mw = fixtures["microwave"]
        cats = [c for c in graspable() if extent(c)[1][2] <= 0.05]
        cat = cats[int(rng.integers(len(cats)))]
        u, v = straighten(mw.yaw, mw.pos[0], mw.pos[1])  # mw's frame: front towards -v, run along +u
        x, y = unstraighten(mw.yaw, u - 0.06 + rng.uniform(-0.03, 0.03), v + rng.uniform(-0.03, 0.03))
        host = host_of(mw, fixtures)
        spots = [f for f in neighbours(host, fixtures) if f.top is not None and f.kind in FLAT_KINDS]
        if not spots:
            # No counter beside the microwave's unit (a stove, sink, fridge, corner piece or the run's
            # end): the nearest counter instead. The unit itself has no room: the plate went into the
            # microwave's body or onto its open door.
            spots = nearest_flat(mw, host, fixtures)
        dest = spots[int(rng.integers(len(spots)))]
        plate = spot_near(fixtures, dest, rng, "plate", y_range=(0.16, 0.2))
        dx = 0.5 * (along(mw, dest) - along(mw, mw)) if same_run(dest, mw) else 0.0
        return Episode(
            self.name,
            f"Pick the {cat} from the microwave and place it on the plate on the counter.",
            spawn(rng, mw, dx=dx, standoff=STANDOFF + 0.1),
            joints=((mw.joints[0], 1.0),),
            objects=(
                Placement(
                    "obj", cat, (float(x), float(y), float(mw.top)), float(rng.uniform(-math.pi, math.pi))
                ),
                Placement("container", "plate", plate),
            ),
            target={"fixture": mw.name, "object": "obj", "container": "container", "destination": dest.name},
        )

    def conditions(self, episode, fixtures, names):
        cat = episode.objects[0].category
        return (
            Condition(
                f"{cat} on the counter plate",
                lambda m, d: pr.in_receptacle(m, d, "obj", "container", "plate"),
            ),
            Condition(
                "gripper far from the object", lambda m, d: pr.gripper_far(m, d, "obj", names.finger_pads)
            ),
        )


TASKS: dict[str, KitchenTask] = {
    t.name: t
    for t in (
        OpenFridge(),
        CloseCabinet(),
        TurnOnStove(),
        PickPlaceCounterToDrawer(),
        PickPlaceMicrowaveToCounter(),
    )
}
"""The atomic tasks by name."""
