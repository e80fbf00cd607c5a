"""H*, the optimal tower height of an instance: an exact dynamic programme over stacking orders.

Model: a tower is a column of pieces, each resting centred on the one below, every piece on an
allowed resting face (for this task: the face it spawns on, any heading). For centred boxes the
contact of two neighbours is the intersection of their footprints; aligning their long sides is
never worse, so the contact's smallest half-width is ``d = min(b_lower, b_upper)`` with ``b`` a
piece's short half-side [m] (the table contact: ``d = b_bottom``). The stack above an interface tips
when tilted by ``atan(d / h)``, ``h`` the height of its centre of mass above the interface; every
interface must keep

    d >= h tan(PHI_MIN),   PHI_MIN = 5 deg.

A piece that cannot support others (the wedge) may only be the top piece.

Exactness: for a set S of boxes with bottom piece p, the height is fixed (sum of thicknesses) and a
lower centre of mass is never worse for what goes below (it only relaxes the next interface and
lowers the next centre of mass), so ``best[S, p]`` = the smallest moment ``sum m_i z_i`` over the
feasible orders suffices: a DP over 2^n x n states (n = 11 boxes: 22,528 states, about a second).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["PHI_MIN_DEG", "Block", "TowerPlan", "optimal_tower"]

PHI_MIN_DEG = 5.0
"""Tipping margin at every interface [deg]."""


@dataclass(frozen=True)
class Block:
    """A piece as the optimiser sees it (resting on its allowed face).

    Attributes:
        name: Piece name.
        b: Short half-side of the resting face [m].
        height: Thickness when resting [m].
        mass: Mass [kg].
        supports: Whether another piece may rest on it.
    """

    name: str
    b: float
    height: float
    mass: float
    supports: bool = True


@dataclass(frozen=True)
class TowerPlan:
    """An optimal tower: ``order`` bottom to top, its ``height`` [m] and worst margin [deg]."""

    order: tuple[str, ...]
    height: float
    worst_margin_deg: float


def _margin_ok(d: float, h: float, tan_phi: float) -> bool:
    return d >= h * tan_phi - 1e-15


def margins(blocks: list[Block], order: tuple[str, ...]) -> list[float]:
    """Tipping angle [deg] at every interface of ``order`` (bottom to top), the table's first."""
    by = {b.name: b for b in blocks}
    stack = [by[n] for n in order]
    out = []
    for i in range(len(stack)):
        above = stack[i:]
        base = sum(s.height for s in stack[:i])
        z = base
        moment, mass = 0.0, 0.0
        for s in above:
            moment += s.mass * (z + s.height / 2 - base)
            mass += s.mass
            z += s.height
        d = stack[i].b if i == 0 else min(stack[i].b, stack[i - 1].b)
        out.append(math.degrees(math.atan2(d, moment / mass)))
    return out


def optimal_tower(blocks: list[Block], phi_min_deg: float = PHI_MIN_DEG) -> TowerPlan:
    """The tallest tower of ``blocks`` with every tipping angle >= ``phi_min_deg`` (see the module docstring)."""
    tan_phi = math.tan(math.radians(phi_min_deg))
    boxes = [b for b in blocks if b.supports]
    tops = [b for b in blocks if not b.supports]
    n = len(boxes)
    # state: (mask, bottom index, top piece index in tops or -1) -> (moment about the bottom face, mass, order)
    best: dict[int, dict[tuple[int, int], tuple[float, float, tuple[str, ...]]]] = {}
    for i, p in enumerate(boxes):
        layer = best.setdefault(1 << i, {})
        layer[(i, -1)] = (p.mass * p.height / 2, p.mass, (p.name,))
        for t, w in enumerate(tops):
            h = w.height / 2
            if _margin_ok(min(p.b, w.b), h, tan_phi):
                moment = w.mass * (p.height + h) + p.mass * p.height / 2
                layer[(i, t)] = (moment, p.mass + w.mass, (p.name, w.name))
    for mask in range(1, 1 << n):
        for (q, t), (moment, mass, order) in best.get(mask, {}).items():
            for i, p in enumerate(boxes):
                if mask & (1 << i):
                    continue
                if not _margin_ok(min(p.b, boxes[q].b), moment / mass, tan_phi):
                    continue
                new = (moment + mass * p.height + p.mass * p.height / 2, mass + p.mass, (p.name, *order))
                layer = best.setdefault(mask | (1 << i), {})
                if (i, t) not in layer or new[0] < layer[(i, t)][0]:
                    layer[(i, t)] = new
    plan = TowerPlan((), 0.0, 90.0)
    for mask, layer in best.items():
        for (i, t), (moment, mass, order) in layer.items():
            if not _margin_ok(boxes[i].b, moment / mass, tan_phi):
                continue
            height = sum(boxes[j].height for j in range(n) if mask & (1 << j))
            height += tops[t].height if t >= 0 else 0.0
            if height > plan.height + 1e-12:
                plan = TowerPlan(order, height, min(margins(blocks, order)))
    return plan
