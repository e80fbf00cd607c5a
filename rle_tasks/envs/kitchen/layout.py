"""Procedural kitchen layouts from a seed: one straight counter run against a wall.

A ``Layout`` is plain data sampled from a ``numpy`` Generator (``sample_layout``): the order and
widths of the base units (a fridge at one end; a stove, a sink, two drawer cabinets, two hinged-door
cabinets and one or two plain counters in a random order), the hinge side of every door, which unit
carries the microwave and which the dish rack, the wall cabinets above the units, and the colours.
``build_layout`` adds the fixtures, the wall and the lights to an ``MjSpec`` and returns them by name.

Names: ``fridge``, ``stove``, ``sink``, ``microwave``, ``dish_rack``, ``drawer_<k>``, ``cabinet_<k>``,
``counter_<k>`` and ``wall_cabinet_<k>`` (k from 0, left to right along +x).
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from rle_tasks.envs.kitchen import appliances, cabinetry
from rle_tasks.envs.kitchen import fixture as fx

__all__ = ["Layout", "Unit", "build_layout", "sample_layout"]

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


@dataclass(frozen=True)
class Unit:
    """One base unit of the run.

    Attributes:
        kind: ``fridge``, ``stove``, ``sink``, ``drawer_cabinet``, ``hinge_cabinet`` or ``counter``.
        width: Width along x [m].
        hinge_left: Door hinged on its left edge (doors only).
        wall_cabinet: A wall cabinet hangs above it.
        wall_hinge_left: Hinge side of that wall cabinet's door.
    """

    kind: str
    width: float
    hinge_left: bool = True
    wall_cabinet: bool = False
    wall_hinge_left: bool = True


@dataclass(frozen=True)
class Layout:
    """A sampled kitchen.

    Attributes:
        units: Base units from left (-x) to right.
        microwave_on: Index of the unit whose counter top carries the microwave.
        dish_rack_on: Index of the unit whose counter top carries the dish rack.
        style: Colours.
    """

    units: tuple[Unit, ...]
    microwave_on: int
    dish_rack_on: int
    style: fx.Style

    @property
    def length(self) -> float:
        return float(sum(u.width for u in self.units))

    def unit_x(self, index: int) -> float:
        """x of the centre of unit ``index`` (the run is centred on x = 0) [m]."""
        left = -self.length / 2 + sum(u.width for u in self.units[:index])
        return left + self.units[index].width / 2


def _pick(rng: np.random.Generator, options: tuple) -> tuple:
    return options[int(rng.integers(len(options)))]


def sample_layout(rng: np.random.Generator) -> Layout:
    """A random kitchen (see the module docstring)."""
    middle = [
        fx_unit
        for fx_unit in (
            Unit("stove", 0.76),
            Unit("sink", float(rng.choice([0.8, 0.9]))),
            Unit("drawer_cabinet", float(rng.choice([0.5, 0.6, 0.7]))),
            Unit("drawer_cabinet", float(rng.choice([0.5, 0.6]))),
            Unit("hinge_cabinet", float(rng.choice([0.5, 0.6])), bool(rng.integers(2))),
            Unit("hinge_cabinet", float(rng.choice([0.5, 0.6])), bool(rng.integers(2))),
            Unit("counter", float(rng.choice([0.7, 0.8, 0.9]))),
        )
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
    flat = [
        i
        for i, u in enumerate(units)
        if u.kind in ("counter", "drawer_cabinet", "hinge_cabinet") and u.width >= 0.6
    ]
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
        free = [
            i
            for i, u in enumerate(units)
            if u.kind in ("counter", "drawer_cabinet", "hinge_cabinet") and i != microwave_on
        ]
        dish_rack_on = min(free, key=lambda i: (abs(i - sink), i))
    style = fx.Style(
        cabinet=_pick(rng, _CABINET_COLOURS),
        counter=_pick(rng, _COUNTER_COLOURS),
        floor=_pick(rng, _FLOOR_COLOURS),
        wall=_pick(rng, _WALL_COLOURS),
    )
    return Layout(tuple(units), microwave_on, dish_rack_on, style)


def build_layout(spec: mujoco.MjSpec, layout: Layout) -> dict[str, fx.Fixture]:
    """Add the wall, the fixtures and the lights of ``layout`` to ``spec``; returns the fixtures by name."""
    world = spec.worldbody
    style = layout.style
    half = layout.length / 2 + 1.5
    world.add_geom(
        name="wall",
        type=mujoco.mjtGeom.mjGEOM_BOX,
        size=[half, 0.05, 1.3],
        pos=[0, 0.05, 1.3],
        rgba=list(style.wall),
    )
    out: dict[str, fx.Fixture] = {}
    counts: dict[str, int] = {}

    def name_of(kind: str) -> str:
        k = counts.get(kind, 0)
        counts[kind] = k + 1
        return f"{kind}_{k}"

    wall_k = 0
    for i, unit in enumerate(layout.units):
        x = layout.unit_x(i)
        if unit.kind == "fridge":
            f = appliances.add_fridge(world, "fridge", x, unit.width, unit.hinge_left, style)
        elif unit.kind == "stove":
            f = appliances.add_stove(world, "stove", x, unit.width, style)
            world.add_geom(
                name="range_hood", type=mujoco.mjtGeom.mjGEOM_BOX, size=[unit.width / 2, 0.25, 0.12],
                pos=[x, -0.25, 1.75], rgba=list(style.appliance),
            )  # fmt: skip
        elif unit.kind == "sink":
            f = appliances.add_sink(world, "sink", x, unit.width, style)
        elif unit.kind == "drawer_cabinet":
            f = cabinetry.add_drawer_cabinet(world, name_of("drawer"), x, unit.width, style)
        elif unit.kind == "hinge_cabinet":
            f = cabinetry.add_hinge_cabinet(world, name_of("cabinet"), x, unit.width, unit.hinge_left, style)
        else:
            f = cabinetry.add_counter(world, name_of("counter"), x, unit.width, style)
        out[f.name] = f
        if unit.wall_cabinet:
            w = cabinetry.add_wall_cabinet(
                world, f"wall_cabinet_{wall_k}", x, unit.width, unit.wall_hinge_left, style
            )
            out[w.name] = w
            wall_k += 1
        if i == layout.microwave_on:
            m = appliances.add_microwave(world, "microwave", x, -0.04, style)
            out[m.name] = m
        if i == layout.dish_rack_on:
            r = appliances.add_dish_rack(world, "dish_rack", x, -0.2)
            out[r.name] = r
    world.add_light(
        name="ceiling", pos=[0, -1.2, 2.6], dir=[0, 0.3, -1], diffuse=[0.55, 0.55, 0.55], castshadow=False
    )
    return out
