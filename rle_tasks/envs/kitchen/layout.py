"""Procedural kitchen layouts from a seed: counter runs of base units, by RoboCasa's layout kinds.

A ``Layout`` is plain data sampled from a ``numpy`` Generator (``sample_one_wall``; every kind: ``layout_kinds.sample_layout``): its runs (``Run``:
a straight row of base units with an origin and a yaw; the units face the run's -y side in its own
frame), which unit carries the microwave and which the dish rack, the wall cabinets above the units,
and the style (colours, handle type, counter height and depth). ``build_layout`` adds the walls, the
fixtures and the lights to an ``MjSpec`` and returns the fixtures by name (in the world frame, with
their facing yaw: ``Fixture.placed``).

Kinds (``KINDS``): ``one_wall``, today's kitchen and the default: one run along +x against a wall at
y = 0, centred on x = 0 (a fridge at one end; a stove, a sink, two drawer cabinets, two hinged-door
cabinets and one or two plain counters in a random order); ``sample_one_wall(rng)`` draws it exactly as
before this module knew other kinds, so its scenes and their digests are unchanged. The other kinds
(``l_shaped``, ``u_shaped``, ``galley``, ``island``, ``peninsula``) are drawn by ``layout_kinds``,
their styles by ``styles`` (which also splits kind x style family into pretrain and target).

Names: ``fridge``, ``stove``, ``sink``, ``microwave``, ``dish_rack``, ``drawer_<k>``, ``cabinet_<k>``,
``counter_<k>``, ``corner_<k>`` and ``wall_cabinet_<k>`` (k from 0, run by run, along each run's +x).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from rle_tasks.envs.kitchen import appliances, cabinetry
from rle_tasks.envs.kitchen import fixture as fx
from rle_tasks.envs.kitchen.styles import KINDS

__all__ = ["CORNER_LEG", "KINDS", "Layout", "Run", "Unit", "build_layout", "sample_one_wall"]

CORNER_LEG = 0.1
"""How far a corner piece reaches past the counter depth along the perpendicular run [m]."""

_CABINET_COLOURS = (
    (0.86, 0.86, 0.83, 1.0),
    (0.62, 0.46, 0.32, 1.0),
    (0.32, 0.40, 0.48, 1.0),
    (0.45, 0.55, 0.42, 1.0),
    (0.93, 0.93, 0.93, 1.0),
    (0.20, 0.21, 0.23, 1.0),
)
_COUNTER_COLOURS = (
    (0.35, 0.33, 0.32, 1.0),
    (0.88, 0.87, 0.84, 1.0),
    (0.55, 0.42, 0.30, 1.0),
    (0.15, 0.15, 0.17, 1.0),
)
_FLOOR_COLOURS = (
    (0.55, 0.45, 0.36, 1.0),
    (0.72, 0.70, 0.66, 1.0),
    (0.40, 0.30, 0.22, 1.0),
    (0.62, 0.64, 0.66, 1.0),
)
_WALL_COLOURS = ((0.93, 0.91, 0.86, 1.0), (0.82, 0.86, 0.88, 1.0), (0.90, 0.84, 0.78, 1.0))
FLAT = ("counter", "drawer_cabinet", "hinge_cabinet")
"""Unit kinds with a plain counter top (the microwave and the dish rack stand on them)."""


@dataclass(frozen=True)
class Unit:
    """One base unit of a run.

    Attributes:
        kind: ``fridge``, ``stove``, ``sink``, ``drawer_cabinet``, ``hinge_cabinet``, ``counter`` or
            ``corner`` (a blind corner piece, ``cabinetry.add_corner``).
        width: Width along the run [m].
        hinge_left: Door hinged on its left (-x) edge (doors only).
        wall_cabinet: A wall cabinet hangs above it.
        wall_hinge_left: Hinge side of that wall cabinet's door.
        corner_side: End of the run a corner piece sits at (+1: +x, -1: -x; corner pieces only).
    """

    kind: str
    width: float
    hinge_left: bool = True
    wall_cabinet: bool = False
    wall_hinge_left: bool = True
    corner_side: int = 0


@dataclass(frozen=True)
class Run:
    """A straight row of base units.

    Its frame: ``origin`` (world xy of the middle of its back line) and ``yaw`` (rotation about z); in
    it the back line is y = 0, the units stand at y < 0 facing -y and follow each other along +x from
    ``-length / 2 + lead``.

    Attributes:
        units: Units in the order of +x.
        origin: World xy of the run frame's origin [m].
        yaw: Rotation of the run frame [rad].
        wall: A wall stands behind it (wall cabinets and the range hood need one).
        lead: Floor left free before the first unit (another run's corner piece reaches into it) [m].
        tail: The same after the last unit [m].
    """

    units: tuple[Unit, ...]
    origin: tuple[float, float] = (0.0, 0.0)
    yaw: float = 0.0
    wall: bool = True
    lead: float = 0.0
    tail: float = 0.0

    @property
    def length(self) -> float:
        return self.lead + float(sum(u.width for u in self.units)) + self.tail

    def unit_x(self, index: int) -> float:
        """x of the centre of unit ``index`` in the run frame (the run is centred on x = 0) [m]."""
        left = -self.length / 2 + self.lead + sum(u.width for u in self.units[:index])
        return left + self.units[index].width / 2

    def to_world(self, x: float, y: float) -> tuple[float, float]:
        """World xy of the run-frame point (x, y) [m]."""
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        return (self.origin[0] + c * x - s * y, self.origin[1] + s * x + c * y)


@dataclass(frozen=True)
class Layout:
    """A sampled kitchen.

    Attributes:
        runs: The counter runs (the first stands against the back wall y = 0).
        microwave_on: (run, unit) whose counter top carries the microwave.
        dish_rack_on: (run, unit) whose counter top carries the dish rack.
        style: Colours, handle type and dimensions.
        kind: One of ``KINDS``.
        family: Style family (``styles.FAMILIES``), None for the one-wall kitchen's own colours.
    """

    runs: tuple[Run, ...]
    microwave_on: tuple[int, int]
    dish_rack_on: tuple[int, int]
    style: fx.Style
    kind: str = "one_wall"
    family: str | None = None

    @property
    def units(self) -> tuple[Unit, ...]:
        """Every base unit, run by run."""
        return tuple(u for r in self.runs for u in r.units)


def _pick(rng: np.random.Generator, options: tuple) -> tuple:
    return options[int(rng.integers(len(options)))]


def sample_one_wall(rng: np.random.Generator) -> Layout:
    """Today's one-wall kitchen in its own colours (``layout_kinds.sample_layout`` draws every kind)."""
    units, microwave_on, dish_rack_on = _one_wall_units(rng)
    style = fx.Style(
        cabinet=_pick(rng, _CABINET_COLOURS),
        counter=_pick(rng, _COUNTER_COLOURS),
        floor=_pick(rng, _FLOOR_COLOURS),
        wall=_pick(rng, _WALL_COLOURS),
    )
    return Layout((Run(tuple(units)),), (0, microwave_on), (0, dish_rack_on), style)


def _one_wall_units(rng: np.random.Generator) -> tuple[list[Unit], int, int]:
    """The one-wall run's units, the microwave's and the dish rack's unit (today's draws, in order)."""
    middle = [
        Unit("stove", 0.76),
        Unit("sink", float(rng.choice([0.8, 0.9]))),
        Unit("drawer_cabinet", float(rng.choice([0.5, 0.6, 0.7]))),
        Unit("drawer_cabinet", float(rng.choice([0.5, 0.6]))),
        Unit("hinge_cabinet", float(rng.choice([0.5, 0.6])), bool(rng.integers(2))),
        Unit("hinge_cabinet", float(rng.choice([0.5, 0.6])), bool(rng.integers(2))),
        Unit("counter", float(rng.choice([0.7, 0.8, 0.9]))),
    ]
    if rng.random() < 0.5:
        middle.append(Unit("counter", float(rng.choice([0.6, 0.8]))))
    order = rng.permutation(len(middle))
    units = [middle[i] for i in order]
    fridge = Unit("fridge", float(rng.choice([0.75, 0.8])), bool(rng.integers(2)))
    units = [fridge, *units] if rng.random() < 0.5 else [*units, fridge]
    units = [
        Unit(
            u.kind,
            u.width,
            u.hinge_left,
            u.kind not in ("fridge", "stove") and rng.random() < 0.8,
            bool(rng.integers(2)),
        )
        for u in units
    ]
    flat = [i for i, u in enumerate(units) if u.kind in FLAT and u.width >= 0.6]
    microwave_on = int(rng.choice(flat))
    sink = next(i for i, u in enumerate(units) if u.kind == "sink")
    beside = [
        i
        for i in (sink - 1, sink + 1)
        if 0 <= i < len(units) and units[i].kind not in ("fridge", "stove") and i != microwave_on
    ]
    if beside:
        dish_rack_on = int(rng.choice(beside))
    else:  # no free flat unit beside the sink: the nearest one
        free = [i for i, u in enumerate(units) if u.kind in FLAT and i != microwave_on]
        dish_rack_on = min(free, key=lambda i: (abs(i - sink), i))
    return units, microwave_on, dish_rack_on


def _wall_margins(layout: Layout, k: int) -> tuple[float, float]:
    """How far run ``k``'s wall reaches past its two ends: 0.1 m (the other wall's thickness) at a
    corner, 1.5 m at a free end [m]."""
    run = layout.runs[k]
    ends = [run.lead > 0 or run.units[0].kind == "corner", run.tail > 0 or run.units[-1].kind == "corner"]
    if layout.kind == "peninsula" and k == 0:
        ends[1] = False  # the peninsula stands free: the back wall goes on past it
    return tuple(0.1 if corner else 1.5 for corner in ends)


def build_layout(spec: mujoco.MjSpec, layout: Layout) -> dict[str, fx.Fixture]:
    """Add the walls, the fixtures and the lights of ``layout`` to ``spec``; returns the fixtures by name."""
    world = spec.worldbody
    style = layout.style
    out: dict[str, fx.Fixture] = {}
    counts: dict[str, int] = {}

    def name_of(kind: str) -> str:
        k = counts.get(kind, 0)
        counts[kind] = k + 1
        return f"{kind}_{k}"

    wall_k = 0
    for r, run in enumerate(layout.runs):
        identity = run.origin == (0.0, 0.0) and run.yaw == 0.0
        parent = world
        if not identity:
            quat = [math.cos(run.yaw / 2), 0.0, 0.0, math.sin(run.yaw / 2)]
            parent = world.add_body(name=f"run_{r}", pos=[run.origin[0], run.origin[1], 0.0], quat=quat)
        if run.wall:
            lo, hi = _wall_margins(layout, r) if layout.kind != "one_wall" else (1.5, 1.5)
            wall_name = "wall" if r == 0 else f"wall_{r}"
            parent.add_geom(
                name=wall_name,
                type=mujoco.mjtGeom.mjGEOM_BOX,
                size=[run.length / 2 + (lo + hi) / 2, 0.05, 1.3],
                pos=[(hi - lo) / 2, 0.05, 1.3],
                rgba=list(style.wall),
            )
        for i, unit in enumerate(run.units):
            x = run.unit_x(i)
            f = _add_unit(parent, unit, x, style, name_of)
            out[f.name] = f.placed(run.origin, run.yaw)
            if unit.kind == "stove" and run.wall:
                parent.add_geom(
                    name="range_hood", type=mujoco.mjtGeom.mjGEOM_BOX, size=[unit.width / 2, 0.25, 0.12],
                    pos=[x, -0.25, 1.75], rgba=list(style.appliance),
                )  # fmt: skip
            if unit.wall_cabinet:
                w = cabinetry.add_wall_cabinet(
                    parent, f"wall_cabinet_{wall_k}", x, unit.width, unit.wall_hinge_left, style
                )
                out[w.name] = w.placed(run.origin, run.yaw)
                wall_k += 1
            if (r, i) == layout.microwave_on:
                m = appliances.add_microwave(parent, "microwave", x, -0.04, style)
                out[m.name] = m.placed(run.origin, run.yaw)
            if (r, i) == layout.dish_rack_on:
                d = appliances.add_dish_rack(parent, "dish_rack", x, -0.2, style)
                out[d.name] = d.placed(run.origin, run.yaw)
    light = [0, -1.2, 2.6]
    if layout.kind != "one_wall":
        xy = np.array([f.pos[:2] for f in out.values()])
        light = [float(xy[:, 0].mean()), float(xy[:, 1].mean()), 2.6]
    world.add_light(name="ceiling", pos=light, dir=[0, 0.3, -1], diffuse=[0.55, 0.55, 0.55], castshadow=False)
    return out


def _add_unit(parent: mujoco.MjsBody, unit: Unit, x: float, style: fx.Style, name_of) -> fx.Fixture:
    """Build one base unit at x along its run (in the frame of ``parent``)."""
    if unit.kind == "fridge":
        return appliances.add_fridge(parent, "fridge", x, unit.width, unit.hinge_left, style)
    if unit.kind == "stove":
        return appliances.add_stove(parent, "stove", x, unit.width, style)
    if unit.kind == "sink":
        return appliances.add_sink(parent, "sink", x, unit.width, style)
    if unit.kind == "drawer_cabinet":
        return cabinetry.add_drawer_cabinet(parent, name_of("drawer"), x, unit.width, style)
    if unit.kind == "hinge_cabinet":
        return cabinetry.add_hinge_cabinet(parent, name_of("cabinet"), x, unit.width, unit.hinge_left, style)
    if unit.kind == "corner":
        name = name_of("corner")
        return cabinetry.add_corner(parent, name, x, unit.width, CORNER_LEG, unit.corner_side, style)
    return cabinetry.add_counter(parent, name_of("counter"), x, unit.width, style)
