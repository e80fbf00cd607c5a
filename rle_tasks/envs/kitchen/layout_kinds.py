"""RoboCasa's layout kinds beyond the one-wall kitchen: how units are shared out over runs, corner
pieces, wall cabinets and appliances placed by rule, and where each run stands.

Every kind starts from run A, along the back wall (frame = world: origin (0, 0), yaw 0, as the one-wall
kitchen). ``D`` is the style's counter depth, ``CORNER_LEG`` = 0.1 m.

- ``l_shaped``: A ends (+x) in a corner piece ``D + 0.1`` wide; run B stands against the right wall
  (yaw -pi/2, back line x = +L_A/2), its first ``D + 0.1`` left to the corner piece (``Run.lead``).
- ``u_shaped``: A has a corner piece at both ends; B on the right wall as above, C on the left wall
  (yaw +pi/2), its last ``D + 0.1`` left to the corner piece (``Run.tail``).
- ``galley``: B against the opposite wall (yaw pi), an aisle of 1.3-1.5 m between the fronts (at least
  1.2 m beside the deeper fridge).
- ``island``: a free-standing island run (yaw pi, no wall) facing A across a 1.3-1.5 m aisle.
- ``peninsula``: as ``l_shaped`` but the second run stands free (no wall behind it).

Rules: the fridge stands at a run's free end (never beside a corner), hinged on its outer side; the stove on a wall run (the range
hood above it); stove and sink are never corner pieces; a hinged door beside a corner is hinged on its
side away from the corner (its handle then swings clear of the other run); wall cabinets hang over 80 %
of a wall run's units, never over the fridge, the stove or a corner piece; the microwave stands on a
flat unit (counter, drawer or door cabinet) at least 0.6 m wide, the dish rack on a flat unit beside the
sink (else the nearest flat unit of its run). Widths [m]: drawer cabinets 0.5-0.8, door cabinets
0.5-0.7, counters 0.6-1.0, sink 0.8-0.9, stove 0.76, fridge 0.75-0.9 (RoboCasa's base stacks are
0.35-1.0 m wide, its fridges 0.9 m).
"""

from __future__ import annotations

import math

import numpy as np

from rle_tasks.envs.kitchen.layout import (
    CORNER_LEG,
    FLAT,
    Layout,
    Run,
    Unit,
    _one_wall_units,
    sample_one_wall,
)
from rle_tasks.envs.kitchen.styles import FAMILIES, KINDS, combinations, sample_style

__all__ = ["AISLES", "sample_kind", "sample_layout", "sample_part"]

AISLES = (1.3, 1.4, 1.5)
"""Aisle widths between facing runs' fronts (galley, island) [m]."""


def _choice(rng: np.random.Generator, options) -> float:
    return float(options[int(rng.integers(len(options)))])


def _pool(rng: np.random.Generator, drawers: int, doors: int, counters: int) -> list[Unit]:
    out = [Unit("drawer_cabinet", _choice(rng, (0.5, 0.6, 0.7, 0.8))) for _ in range(drawers)]
    out += [Unit("hinge_cabinet", _choice(rng, (0.5, 0.6, 0.7)), bool(rng.integers(2))) for _ in range(doors)]
    out += [Unit("counter", _choice(rng, (0.6, 0.7, 0.8, 0.9, 1.0))) for _ in range(counters)]
    return [out[i] for i in rng.permutation(len(out))]


def _deal(rng: np.random.Generator, runs: list[list[Unit]], pool: list[Unit], least: list[int]) -> None:
    """Give every run at least ``least`` units from ``pool``, the rest at random; shuffle each run."""
    for r, n in enumerate(least):
        while len(runs[r]) < n and pool:
            runs[r].append(pool.pop())
    for u in pool:
        runs[int(rng.integers(len(runs)))].append(u)
    for r, units in enumerate(runs):
        runs[r] = [units[i] for i in rng.permutation(len(units))]


def sample_layout(rng: np.random.Generator, kind: str = "one_wall", family: str | None = None) -> Layout:
    """A random kitchen of ``kind`` in style ``family`` (None: the one-wall kitchen's own colours for
    ``one_wall``, a random family otherwise). ``sample_layout(rng)`` is today's one-wall kitchen
    (``layout.sample_one_wall``)."""
    if kind not in KINDS:
        raise ValueError(f"unknown layout kind {kind!r}; kinds: {', '.join(KINDS)}")
    if kind == "one_wall" and family is None:
        return sample_one_wall(rng)
    return sample_kind(rng, kind, family)


def sample_kind(rng: np.random.Generator, kind: str, family: str | None) -> Layout:
    """A random kitchen of ``kind`` in style ``family`` (None: one drawn at random)."""
    if family is None:
        family = list(FAMILIES)[int(rng.integers(len(FAMILIES)))]
    style = sample_style(rng, family)
    if kind == "one_wall":
        units, mw, rack = _one_wall_units(rng)
        return Layout((Run(tuple(units)),), (0, mw), (0, rack), style, kind, family)
    d = style.counter_depth
    stove, sink = Unit("stove", 0.76), Unit("sink", _choice(rng, (0.8, 0.9)))
    fridge = Unit("fridge", _choice(rng, (0.75, 0.8, 0.9)), bool(rng.integers(2)))
    corner = d + CORNER_LEG
    if kind in ("l_shaped", "galley"):
        runs: list[list[Unit]] = [[stove], [sink]] if rng.random() < 0.5 else [[sink], [stove]]
        _deal(rng, runs, _pool(rng, 2, 2, 2), [3, 3])
    elif kind == "u_shaped":
        runs = [[sink], [stove], []] if rng.random() < 0.5 else [[sink], [], [stove]]
        _deal(rng, runs, _pool(rng, 3, 2, 2), [2, 2, 2])
    else:  # island, peninsula: the wall run holds the stove, the free run 2-3 flat units (and the sink?)
        free = [sink] if rng.random() < 0.5 else []
        runs = [[stove] if free else [stove, sink], free]
        _deal(rng, runs, _pool(rng, 2, 2, 1 + int(rng.integers(2))), [5, 2 if free else 3])
    # the fridge at a free end
    ends = {
        "l_shaped": [(0, 0), (1, -1)],
        "u_shaped": [(1, -1), (2, 0)],
        "galley": [(0, 0), (0, -1), (1, 0), (1, -1)],
        "island": [(0, 0), (0, -1)],
        "peninsula": [(0, 0)],
    }[kind]
    r, end = ends[int(rng.integers(len(ends)))]
    # hinged on its outer side: the door opens towards the free floor past the run's end, not across
    # the counter (a robot opening it walks round the hinge, clear of a facing run or island)
    fridge = Unit("fridge", fridge.width, end == 0)
    runs[r] = [fridge, *runs[r]] if end == 0 else [*runs[r], fridge]
    # corner pieces and the runs' frames
    if kind in ("l_shaped", "peninsula", "u_shaped"):
        runs[0] = [*runs[0], Unit("corner", corner, corner_side=1)]
    if kind == "u_shaped":
        runs[0] = [Unit("corner", corner, corner_side=-1), *runs[0]]
    walls = {"l_shaped": 2, "u_shaped": 3, "galley": 2, "island": 1, "peninsula": 1}[kind]
    runs = [_with_wall_cabinets(rng, u, r < walls) for r, u in enumerate(runs)]
    lead_tail = {1: (corner, 0.0), 2: (0.0, corner)} if kind in ("l_shaped", "u_shaped", "peninsula") else {}
    plain = [Run(tuple(_fix_hinges(u, *lead_tail.get(r, (0.0, 0.0))))) for r, u in enumerate(runs)]
    built = _place_runs(rng, kind, plain, d, lead_tail, walls)
    mw, rack = _appliances(rng, built)
    return Layout(tuple(built), mw, rack, style, kind, family)


def sample_part(rng: np.random.Generator, part: str) -> Layout:
    """A kitchen of a (kind, style family) combination of ``part`` (``pretrain`` or ``target``, see
    ``styles.split``), the combination drawn uniformly (``scene.build_scene`` with a ``part``)."""
    combos = combinations(part)
    kind, family = combos[int(rng.integers(len(combos)))]
    return sample_kind(rng, kind, family)


def _with_wall_cabinets(rng: np.random.Generator, units: list[Unit], wall: bool) -> list[Unit]:
    return [
        Unit(
            u.kind,
            u.width,
            u.hinge_left,
            wall and u.kind not in ("fridge", "stove", "corner") and rng.random() < 0.8,
            bool(rng.integers(2)),
            u.corner_side,
        )
        for u in units
    ]


def _fix_hinges(units: list[Unit], lead: float, tail: float) -> list[Unit]:
    """Hinge the doors of a unit beside a corner (a corner piece, or the run's lead or tail) on the
    side away from it."""
    out = list(units)
    for i, u in enumerate(out):
        before = (i == 0 and lead > 0) or (i > 0 and out[i - 1].kind == "corner")
        after = (i == len(out) - 1 and tail > 0) or (i + 1 < len(out) and out[i + 1].kind == "corner")
        if before != after and u.kind != "corner":
            out[i] = Unit(u.kind, u.width, after, u.wall_cabinet, after, u.corner_side)
    return out


def _place_runs(
    rng: np.random.Generator, kind: str, runs: list[Run], d: float, lead_tail: dict, walls: int
) -> list[Run]:
    """The runs with their frames (see the module docstring)."""
    a = runs[0]
    la = a.length
    out = [a]
    for r, run in enumerate(runs[1:], start=1):
        lead, tail = lead_tail.get(r, (0.0, 0.0))
        run = Run(run.units, wall=r < walls, lead=lead, tail=tail)
        if kind in ("l_shaped", "peninsula", "u_shaped") and r == 1:
            origin, yaw = (la / 2, -run.length / 2), -math.pi / 2
        elif kind == "u_shaped":
            origin, yaw = (-la / 2, -run.length / 2), math.pi / 2
        else:  # galley, island: facing A across the aisle
            aisle = _choice(rng, AISLES)
            origin, yaw = (0.0, -(2 * d + aisle)), math.pi
        out.append(Run(run.units, origin, yaw, run.wall, run.lead, run.tail))
    return out


def _appliances(rng: np.random.Generator, runs: list[Run]) -> tuple[tuple[int, int], tuple[int, int]]:
    """(run, unit) of the microwave and of the dish rack."""
    flat = [(r, i) for r, run in enumerate(runs) for i, u in enumerate(run.units) if u.kind in FLAT]
    wide = [ri for ri in flat if runs[ri[0]].units[ri[1]].width >= 0.6]
    mw = wide[int(rng.integers(len(wide)))]
    sr, si = next((r, i) for r, run in enumerate(runs) for i, u in enumerate(run.units) if u.kind == "sink")
    free = [ri for ri in flat if ri != mw]
    beside = [(sr, i) for i in (si - 1, si + 1) if (sr, i) in free]
    if beside:
        return mw, beside[int(rng.integers(len(beside)))]
    same = [ri for ri in free if ri[0] == sr] or free
    return mw, min(same, key=lambda ri: (ri[0] != sr, abs(ri[1] - si), ri))
