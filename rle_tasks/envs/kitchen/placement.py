"""Where a task's robot and objects go, in the target fixture's own frame, for every layout kind.

A fixture faces ``Fixture.facing`` = (sin yaw, -cos yaw); its run runs along (cos yaw, sin yaw). Every
rule here is written in the fixture's *straightened* frame: the world turned by -yaw about the origin,
so the fixture faces -y and its run runs along +x, as the one-wall kitchen's fixtures do in the world
(``straighten``). A result is turned back by +yaw (``unstraighten``). Both turns are the identity when
yaw is 0 (no arithmetic at all), so a one-wall kitchen's episodes are bit for bit what they were when
the rules were written in world axes.

Fixtures of one run share its yaw, and no two runs of a kitchen share one (``layout_kinds``): "on the
same run" is "of the same yaw" (``same_run``).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from rle_tasks.envs.kitchen.fixture import Fixture
from rle_tasks.envs.kitchen.objects import extent

__all__ = [
    "FLAT_KINDS",
    "SPAWN_NOISE",
    "STANDOFF",
    "along",
    "host_of",
    "nearest_flat",
    "neighbours",
    "on_top",
    "same_run",
    "spawn",
    "spot_near",
    "straighten",
    "unstraighten",
]

FLAT_KINDS = ("counter", "drawer_cabinet", "hinge_cabinet")
"""Kinds of fixture whose counter top objects stand on."""
STANDOFF = 0.55
"""Distance from the robot's arm root to the target fixture's front at spawn [m]."""
SPAWN_NOISE = (0.04, 0.03, 0.05)
"""Half widths of the uniform spawn noise: along the run, towards the fixture [m], heading [rad]."""


def straighten(yaw: float, x: float, y: float) -> tuple[float, float]:
    """World xy turned by ``-yaw`` about the origin (itself when ``yaw`` is 0)."""
    if yaw == 0.0:
        return x, y
    c, s = math.cos(yaw), math.sin(yaw)
    return c * x + s * y, -s * x + c * y


def unstraighten(yaw: float, x: float, y: float) -> tuple[float, float]:
    """Straightened xy turned back by ``yaw`` into the world (itself when ``yaw`` is 0)."""
    if yaw == 0.0:
        return x, y
    c, s = math.cos(yaw), math.sin(yaw)
    return c * x - s * y, s * x + c * y


def _straight(f: Fixture, yaw: float) -> Fixture:
    """``f`` with its ``pos`` in the frame straightened by ``yaw``."""
    if yaw == 0.0:
        return f
    x, y = straighten(yaw, f.pos[0], f.pos[1])
    return replace(f, pos=(x, y, f.pos[2]), yaw=f.yaw - yaw)


def same_run(f: Fixture, g: Fixture) -> bool:
    """``f`` and ``g`` stand on one run (they share its yaw)."""
    return abs(math.remainder(f.yaw - g.yaw, 2 * math.pi)) < 1e-9


def along(f: Fixture, g: Fixture) -> float:
    """Coordinate of ``g``'s centre along ``f``'s run [m] (its world x in a one-wall kitchen)."""
    return straighten(f.yaw, g.pos[0], g.pos[1])[0]


def _distance(f: Fixture, g: Fixture) -> tuple[bool, float]:
    """(other run, distance) of ``g`` from ``f``: along the run on it, straight-line otherwise [m]."""
    if same_run(f, g):
        return False, abs(along(f, g) - along(f, f))
    return True, float(math.hypot(g.pos[0] - f.pos[0], g.pos[1] - f.pos[1]))


def spawn(
    rng: np.random.Generator, fixture: Fixture, dx: float = 0.0, standoff: float = STANDOFF
) -> tuple[float, float, float]:
    """Base pose (x, y, heading) facing ``fixture``: ``standoff`` in front of it, ``dx`` along its run
    (its +x: right of a robot facing it), with the seeded noise ``SPAWN_NOISE``."""
    s = _straight(fixture, fixture.yaw)
    nx, ny, nyaw = SPAWN_NOISE
    x = float(s.pos[0] + dx + rng.uniform(-nx, nx))
    y = float(s.front_y - standoff + rng.uniform(-ny, ny))
    heading = float(math.pi / 2 + rng.uniform(-nyaw, nyaw))
    if fixture.yaw == 0.0:
        return x, y, heading
    wx, wy = unstraighten(fixture.yaw, x, y)
    return float(wx), float(wy), float(math.remainder(heading + fixture.yaw, 2 * math.pi))


def on_top(
    fixture: Fixture,
    rng: np.random.Generator,
    category: str,
    y_range=(0.12, 0.28),
    fixtures: dict[str, Fixture] | None = None,
    taken: tuple[tuple[float, float, float], ...] = (),
) -> tuple[float, float, float]:
    """A spot (world xyz) on ``fixture``'s counter top, clear of a microwave (7 cm: its door and handle
    stand 6 cm proud of its front) or dish rack (1 cm) on its run and of the objects at ``taken`` (world
    x, y, radius; 2 cm). ``y_range``: depth behind the top's front edge [m].

    The depth range shrinks in front of a microwave or dish rack standing on this top, so one draw
    usually lands clear (an object spawned inside the microwave or on the rack's rail fell over, out of
    any gripper's reach); when it does not, up to 200 more draws over the whole top.

    Raises:
        ValueError: No clear spot on this top.
    """
    yaw = fixture.yaw
    top = _straight(fixture, yaw)
    _, half = extent(category)
    r = max(half[0], half[1])
    margin = r + 0.03
    lo, hi = y_range
    blocks = []
    for f in (fixtures or {}).values():
        if f.kind in ("microwave", "dish_rack") and same_run(f, fixture):
            f = _straight(f, yaw)
            front = 0.07 if f.kind == "microwave" else 0.01
            x0, x1 = f.pos[0] - f.size[0] / 2, f.pos[0] + f.size[0] / 2
            blocks.append((x0 - 0.01, x1 + 0.01, f.front_y - front, f.pos[1] + f.size[1] / 2))
            if abs(f.pos[0] - top.pos[0]) < 1e-6:
                hi = min(hi, f.front_y - r - front - top.front_y)
                lo = min(lo, hi)
    taken = tuple((*straighten(yaw, tx, ty), tr) for tx, ty, tr in taken)
    xs = (-top.size[0] / 2 + margin, top.size[0] / 2 - margin)
    for k in range(201):
        ys = (lo, hi) if k == 0 else (r + 0.03, top.size[1] - r - 0.03)
        x = top.pos[0] + rng.uniform(*xs)
        y = top.front_y + rng.uniform(*ys)
        clear = all(x + r < x0 or x - r > x1 or y + r < y0 or y - r > y1 for x0, x1, y0, y1 in blocks)
        clear = clear and all(np.hypot(x - tx, y - ty) > r + tr + 0.02 for tx, ty, tr in taken)
        if clear:
            wx, wy = unstraighten(yaw, x, y)
            return (float(wx), float(wy), float(fixture.top))
    raise ValueError(f"no clear spot for a {category} on {fixture.name}")


def spot_near(
    fixtures: dict[str, Fixture],
    f: Fixture,
    rng: np.random.Generator,
    category: str,
    placements=(),
    y_range: tuple[float, float] = (0.12, 0.28),
) -> tuple[float, float, float]:
    """A clear spot (``on_top``) on the flat counter top nearest to ``f`` (its own top when it has one;
    tops of its run first, nearest along the run), trying the next nearest tops when one is full (the
    microwave or the dish rack may take a top). ``placements``: the episode's ``Placement``s so far.

    Raises:
        ValueError: No flat top in the kitchen has room.
    """
    flat = [g for g in fixtures.values() if g.kind in FLAT_KINDS and g.top is not None]
    flat.sort(key=lambda g: (g.name != f.name, *_distance(f, g), g.name))
    taken = tuple(
        (p.pos[0], p.pos[1], max(extent(p.category)[1][:2]))
        for p in placements
        if p.inside is None and p.on is None
    )
    for host in flat:
        try:
            return on_top(host, rng, category, y_range, fixtures=fixtures, taken=taken)
        except ValueError:
            continue
    raise ValueError(f"no clear counter spot for a {category} near {f.name}")


def host_of(mw: Fixture, fixtures: dict[str, Fixture]) -> Fixture:
    """The base unit a counter-top appliance (the microwave) stands on."""
    u = along(mw, mw)
    base = [
        f
        for f in fixtures.values()
        if f.kind in FLAT_KINDS and same_run(f, mw) and abs(along(mw, f) - u) < 1e-6
    ]
    return base[0]


def neighbours(host: Fixture, fixtures: dict[str, Fixture]) -> list[Fixture]:
    """The base units either side of ``host`` on its run (none past the run's ends or corner pieces'
    far side: a corner piece is a neighbour)."""
    base = sorted(
        (f for f in fixtures.values() if f.pos[2] == 0.0 and f.kind != "wall_cabinet" and same_run(f, host)),
        key=lambda f: along(host, f),
    )
    i = next(k for k, f in enumerate(base) if f.name == host.name)
    return [base[k] for k in (i - 1, i + 1) if 0 <= k < len(base)]


def nearest_flat(mw: Fixture, host: Fixture, fixtures: dict[str, Fixture]) -> list[Fixture]:
    """The flat floor-standing units nearest ``mw`` other than its ``host`` (ties all kept): on its run
    when it has one, anywhere otherwise."""
    flat = [f for f in fixtures.values() if f.pos[2] == 0.0 and f.kind in FLAT_KINDS and f is not host]
    near = min(_distance(mw, f) for f in flat)
    return [f for f in flat if _distance(mw, f)[0] == near[0] and _distance(mw, f)[1] < near[1] + 1e-6]
