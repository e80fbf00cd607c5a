"""H* search: small instances whose optimum is known by hand, and the H* stack in simulation."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.f03_physical_reasoning.scene import CONFIG
from rle_tasks.f03_physical_reasoning.tower.optimum import Block, margins, optimal_tower
from rle_tasks.f03_physical_reasoning.tower.verifier import instance, measure

TAN5 = math.tan(math.radians(5.0))


def test_three_wide_boxes_all_stack() -> None:
    blocks = [Block("a", 0.03, 0.02, 0.1), Block("b", 0.025, 0.03, 0.1), Block("c", 0.02, 0.01, 0.1)]
    plan = optimal_tower(blocks)
    assert plan.height == pytest.approx(0.06)
    assert set(plan.order) == {"a", "b", "c"}


def test_a_post_too_slender_to_stand_is_left_out() -> None:
    # alone on the table the post's centre of mass is 0.05 m up: it needs b >= 0.05 tan 5 deg = 4.4 mm
    blocks = [Block("a", 0.03, 0.02, 0.1), Block("b", 0.03, 0.03, 0.1), Block("post", 0.002, 0.1, 0.05)]
    assert 0.05 * TAN5 > 0.002
    plan = optimal_tower(blocks)
    assert plan.height == pytest.approx(0.05) and "post" not in plan.order


def test_a_post_that_stands_alone_but_not_under_a_load() -> None:
    # post: b = 5 mm, 0.1 m tall, 0.05 kg; alone: 0.005 >= 0.05 tan5 = 4.37 mm (stands, 5.7 deg).
    # a box (b = 0.03, 0.02 m, 0.1 kg) on the post: centre of mass of both above the table
    # (0.05 * 0.05 + 0.1 * 0.11) / 0.15 = 0.09 m -> needs 7.9 mm > 5 mm: not on the post.
    # the post on the box: interface d = 5 mm, h = 0.05 m -> needs 4.37 mm: stands. H* = 0.12 m.
    blocks = [Block("box", 0.03, 0.02, 0.1), Block("post", 0.005, 0.1, 0.05)]
    plan = optimal_tower(blocks)
    assert plan.order == ("box", "post") and plan.height == pytest.approx(0.12)
    assert min(margins(blocks, plan.order)) >= 5.0


def test_the_wedge_only_tops_the_tower() -> None:
    blocks = [
        Block("a", 0.03, 0.02, 0.1),
        Block("w", 0.03, 0.04, 0.05, supports=False),
        Block("b", 0.03, 0.02, 0.1),
    ]
    plan = optimal_tower(blocks)
    assert plan.order[-1] == "w" and plan.height == pytest.approx(0.08)


def test_instance_optimum_stack_placed_with_noise_stands() -> None:
    inst = instance(Secret(PUBLIC_KEY, public=True))
    assert len(inst.pieces) == 12 and inst.plan.worst_margin_deg >= 5.0
    rng = np.random.default_rng(0)
    by = {p.name: p for p in inst.pieces}
    poses, z = {}, CONFIG.top_z
    for name in inst.plan.order:
        h = by[name].half_size[2]
        poses[name] = np.array([0.33 + rng.normal(0, 0.001), rng.normal(0, 0.001), z + h + 1e-4, 1, 0, 0, 0])
        z += 2 * h + 1e-4
    for p in inst.pieces:
        poses.setdefault(p.name, np.array([*p.pos, 1.0, 0.0, 0.0, 0.0]))
    m = measure(inst, poses)
    assert m["ratio"] > 0.99
