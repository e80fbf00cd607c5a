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

The robot starts in front of the target fixture (``Spawn``), facing the wall, with a seeded offset.
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

__all__ = ["TASKS", "Condition", "Episode", "KitchenTask", "Placement"]

FLAT_KINDS = ("counter", "drawer_cabinet", "hinge_cabinet")
"""Kinds of fixture whose counter top objects stand on."""
STANDOFF = 0.55
"""Distance from the robot's arm root to the target fixture's front at spawn [m]."""
SPAWN_NOISE = (0.04, 0.03, 0.05)
"""Half widths of the uniform spawn noise: along the wall, towards it [m], heading [rad]."""


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
        robot: Base pose at spawn: x, y [m], heading [rad] (pi/2 faces the wall).
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


def _spawn(
    rng: np.random.Generator, fixture: Fixture, dx: float = 0.0, standoff: float = STANDOFF
) -> tuple[float, float, float]:
    nx, ny, nyaw = SPAWN_NOISE
    return (
        float(fixture.pos[0] + dx + rng.uniform(-nx, nx)),
        float(fixture.front_y - standoff + rng.uniform(-ny, ny)),
        float(math.pi / 2 + rng.uniform(-nyaw, nyaw)),
    )


def _tops(fixtures: dict[str, Fixture]) -> tuple[str, ...]:
    """Counter-top geoms of every fixture (objects must not touch them to count as inside)."""
    return tuple(
        g for f in fixtures.values() if f.kind not in ("microwave", "dish_rack") for g in f.top_geoms
    )


def _on_top(
    fixture: Fixture,
    rng: np.random.Generator,
    category: str,
    y_range=(0.12, 0.28),
    fixtures: dict[str, Fixture] | None = None,
    taken: tuple[tuple[float, float, float], ...] = (),
) -> tuple[float, float, float]:
    """A spot on ``fixture``'s counter top, clear of a microwave (7 cm: its door and handle stand 6 cm
    proud of its front) or dish rack (1 cm) and of the objects at ``taken`` (x, y, radius; 2 cm).

    The depth range shrinks in front of a microwave or dish rack standing on this top, so one draw
    usually lands clear (an object spawned inside the microwave or on the rack's rail fell over, out of
    any gripper's reach); when it does not, up to 200 more draws over the whole top.

    Raises:
        ValueError: No clear spot on this top.
    """
    _, half = extent(category)
    r = max(half[0], half[1])
    margin = r + 0.03
    lo, hi = y_range
    blocks = []
    for f in (fixtures or {}).values():
        if f.kind in ("microwave", "dish_rack"):
            front = 0.07 if f.kind == "microwave" else 0.01
            x0, x1 = f.pos[0] - f.size[0] / 2, f.pos[0] + f.size[0] / 2
            blocks.append((x0 - 0.01, x1 + 0.01, f.front_y - front, f.pos[1] + f.size[1] / 2))
            if abs(f.pos[0] - fixture.pos[0]) < 1e-6:
                hi = min(hi, f.front_y - r - front - fixture.front_y)
                lo = min(lo, hi)
    xs = (-fixture.size[0] / 2 + margin, fixture.size[0] / 2 - margin)
    for k in range(201):
        ys = (lo, hi) if k == 0 else (r + 0.03, fixture.size[1] - r - 0.03)
        x = fixture.pos[0] + rng.uniform(*xs)
        y = fixture.front_y + rng.uniform(*ys)
        clear = all(x + r < x0 or x - r > x1 or y + r < y0 or y - r > y1 for x0, x1, y0, y1 in blocks)
        clear = clear and all(np.hypot(x - tx, y - ty) > r + tr + 0.02 for tx, ty, tr in taken)
        if clear:
            return (float(x), float(y), float(fixture.top))
    raise ValueError(f"no clear spot for a {category} on {fixture.name}")


def spot_near(
    fixtures: dict[str, Fixture],
    f: Fixture,
    rng: np.random.Generator,
    category: str,
    placements: tuple[Placement, ...] = (),
    y_range: tuple[float, float] = (0.12, 0.28),
) -> tuple[float, float, float]:
    """A clear spot (``_on_top``) on the flat counter top nearest to ``f`` (its own top when it has one),
    trying the next nearest tops when one is full (the microwave or the dish rack may take a top).

    Raises:
        ValueError: No flat top in the kitchen has room.
    """
    flat = [g for g in fixtures.values() if g.kind in FLAT_KINDS and g.top is not None]
    flat.sort(key=lambda g: (g.name != f.name, abs(g.pos[0] - f.pos[0]), g.name))
    taken = tuple(
        (p.pos[0], p.pos[1], max(extent(p.category)[1][:2]))
        for p in placements
        if p.inside is None and p.on is None
    )
    for host in flat:
        try:
            return _on_top(host, rng, category, y_range, fixtures=fixtures, taken=taken)
        except ValueError:
            continue
    raise ValueError(f"no clear counter spot for a {category} near {f.name}")


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
        robot = _spawn(rng, f, dx=side * (f.size[0] / 2 + 0.05))
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
        robot = _spawn(rng, f, dx=side * (f.size[0] / 2 + 0.3), standoff=STANDOFF + 0.05)
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
            _spawn(rng, f),
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
            _spawn(rng, f, standoff=STANDOFF + 0.1),
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
        x = mw.pos[0] - 0.06 + rng.uniform(-0.03, 0.03)
        y = mw.pos[1] + rng.uniform(-0.03, 0.03)
        host = _host_of(mw, fixtures)
        spots = [
            f
            for f in _neighbours(host, fixtures)
            if f.top is not None and f.kind in ("counter", "drawer_cabinet", "hinge_cabinet")
        ]
        if not spots:
            # No counter beside the microwave's unit (a stove, sink, fridge or the run's end): the
            # nearest counter instead. The unit itself has no room: the plate went into the
            # microwave's body or onto its open door.
            flat = [
                f
                for f in fixtures.values()
                if f.pos[2] == 0.0
                and f.kind in ("counter", "drawer_cabinet", "hinge_cabinet")
                and f is not host
            ]
            near = min(abs(f.pos[0] - mw.pos[0]) for f in flat)
            spots = [f for f in flat if abs(f.pos[0] - mw.pos[0]) < near + 1e-6]
        dest = spots[int(rng.integers(len(spots)))]
        plate = spot_near(fixtures, dest, rng, "plate", y_range=(0.16, 0.2))
        return Episode(
            self.name,
            f"Pick the {cat} from the microwave and place it on the plate on the counter.",
            _spawn(rng, mw, dx=0.5 * (dest.pos[0] - mw.pos[0]), standoff=STANDOFF + 0.1),
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


def _host_of(mw: Fixture, fixtures: dict[str, Fixture]) -> Fixture:
    base = [
        f
        for f in fixtures.values()
        if f.kind in ("counter", "drawer_cabinet", "hinge_cabinet") and abs(f.pos[0] - mw.pos[0]) < 1e-6
    ]
    return base[0]


def _neighbours(host: Fixture, fixtures: dict[str, Fixture]) -> list[Fixture]:
    base = sorted(
        (f for f in fixtures.values() if f.pos[2] == 0.0 and f.kind != "wall_cabinet"), key=lambda f: f.pos[0]
    )
    i = next(k for k, f in enumerate(base) if f.name == host.name)
    return [base[k] for k in (i - 1, i + 1) if 0 <= k < len(base)]


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
