"""Cantilever closed forms: harmonic stacks at -/+3 % of L/2 sum 1/k; the Paterson-Zwick 4-block stack."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import linprog

from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.f03_physical_reasoning.cantilever.scoring import PZ4
from rle_tasks.f03_physical_reasoning.cantilever.verifier import HEIGHT, instance, measure
from rle_tasks.f03_physical_reasoning.scene import CONFIG

INST = instance(Secret(PUBLIC_KEY, public=True))
L = INST.length
MARGIN = 0.03
"""Documented margin: fraction of the harmonic offsets within which the contact model resolves tipping."""
PZ = json.loads((Path(__file__).parents[2] / "rle_tasks/f03_physical_reasoning/assets/pz4.json").read_text())


def _pose(x: float, y: float, level: int, yaw: float = 0.0) -> np.ndarray:
    z = CONFIG.top_z + HEIGHT * (level + 0.5) + 1e-4 * level
    return np.array([x, y, z, math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)])


def _harmonic(n: int, scale: float) -> dict[str, np.ndarray]:
    """n blocks, block k from the top overhanging the one below by scale x L/(2k); the rest aside."""
    poses = {}
    for level in range(n):
        k = n - level
        right = CONFIG.edge_x + 0.5 * L * scale * sum(1.0 / j for j in range(k, n + 1))
        poses[f"block{level}"] = _pose(right - L / 2, 0.0, level)
    for i in range(n, 4):
        poses[f"block{i}"] = _pose(0.1, -0.3 + 0.1 * i, 0)
    return poses


@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_harmonic_stack_stands_below_and_falls_above_its_closed_form(n: int) -> None:
    closed = 0.5 * L * sum(1.0 / k for k in range(1, n + 1))  # L/2 H_n
    inside = measure(INST, _harmonic(n, 1.0 - MARGIN))
    assert inside["blocks_on_table"] == 4
    assert inside["overhang_m"] == pytest.approx((1.0 - MARGIN) * closed, abs=1.5e-3)
    outside = measure(INST, _harmonic(n, 1.0 + MARGIN))
    assert outside["blocks_on_table"] < 4  # the top block fell
    assert outside["overhang_m"] < closed


def _equilibrium_feasible(lefts: list[float], margin: float = 0.0) -> bool:
    """2-D LP: non-negative support forces at the ends of each contact interval (shrunk by ``margin``)
    balance every unit block's weight and moment (block length 1, table edge at 0)."""
    supports = [(0, -1), (1, 0), (2, 0), (3, 1), (3, 2)]
    points = []
    for upper, lower in supports:
        lo = max(lefts[upper], lefts[lower] if lower >= 0 else -1e3) + margin
        hi = min(lefts[upper] + 1, lefts[lower] + 1 if lower >= 0 else 0.0) - margin
        if hi < lo:
            return False
        points += [(upper, lower, lo), (upper, lower, hi)]
    a = np.zeros((8, len(points)))
    for k, (upper, lower, x) in enumerate(points):
        a[2 * upper, k] += 1
        a[2 * upper + 1, k] += x
        if lower >= 0:
            a[2 * lower, k] -= 1
            a[2 * lower + 1, k] -= x
    b = np.ravel([[1.0, left + 0.5] for left in lefts])
    res = linprog(np.zeros(len(points)), A_eq=a, b_eq=b, bounds=[(0, None)] * len(points), method="highs")
    return res.status == 0


def test_paterson_zwick_configuration_is_the_critical_optimum() -> None:
    opt = PZ["optimum"]
    assert pytest.approx((15 - 4 * math.sqrt(2)) / 8) == PZ4
    assert max(opt[0], opt[2]) + 1 == pytest.approx(PZ4, abs=1e-4)
    assert _equilibrium_feasible(opt)
    pushed = list(opt)
    pushed[2] += 0.002  # the overhanging block 0.2 % of L further out: no equilibrium
    assert not _equilibrium_feasible(pushed)
    assert _equilibrium_feasible(PZ["margin_0.03"], margin=0.03)
    assert max(PZ["margin_0.03"][0], PZ["margin_0.03"][2]) + 1 > 0.93 * PZ4


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_paterson_zwick_stack_with_margin_stands_under_placement_noise(seed: int) -> None:
    rng = np.random.default_rng(seed)
    poses = {}
    for i, (left, level) in enumerate(zip(PZ["margin_0.03"], PZ["levels"])):
        x = CONFIG.edge_x + (left + 0.5) * L + rng.normal(0, 0.001)
        poses[f"block{i}"] = _pose(x, rng.normal(0, 0.001), level, rng.normal(0, math.radians(0.5)))
    m = measure(INST, poses)
    assert m["blocks_on_table"] == 4
    assert m["ratio"] > 0.92  # margin 0.03 L: overhang 1.0978 L = 0.94 of the optimum


def test_yaw_never_lengthens_a_block() -> None:
    straight = measure(INST, _harmonic(1, 0.9))["overhang_m"]
    poses = _harmonic(1, 0.9)
    poses["block0"] = _pose(poses["block0"][0], 0.0, 0, math.radians(30))
    assert measure(INST, poses)["overhang_m"] < straight
