"""Every kitchen task builds in many kitchens, starts unsolved and stable, and its scenes replay alike."""

import mujoco
import numpy as np
import pytest

from rle_tasks.envs.kitchen.composite_tasks import COMPOSITES
from rle_tasks.envs.kitchen.env import KitchenEnv
from rle_tasks.envs.kitchen.scene import build_scene
from rle_tasks.envs.kitchen.sessions import pretrain_seed
from rle_tasks.envs.kitchen.tasks import TASKS


def _kitchens(full_battery: bool, reduced: int, full: int) -> range:
    return range(full if full_battery else reduced)


def _check(task: str, layout: int, episode: int) -> None:
    scene = build_scene(layout, task, episode)
    env = KitchenEnv(xml=scene.xml, scene=scene, level=3, image_size=None)
    model = env.build()
    data = mujoco.MjData(model)
    env.reset(model, data)
    start = env.conditions(model, data)
    assert start and not all(start.values()), (task, layout, start)
    hold = np.zeros(12)
    hold[6] = hold[11] = -1.0
    for _ in range(10):
        env.step(model, data, hold)
    assert env.conditions(model, data) == start, (task, layout)
    assert not any(w.number for w in data.warning), (task, layout)


@pytest.mark.physics
@pytest.mark.parametrize("task", list(TASKS))
def test_atomic_tasks_build_in_every_pretrain_kitchen(task, full_battery):
    for k in _kitchens(full_battery, 6, 50):
        _check(task, pretrain_seed(k), k)


@pytest.mark.physics
def test_composite_tasks_build_and_start_unsolved(full_battery):
    for name in COMPOSITES:
        for k in _kitchens(full_battery, 1, 5):
            _check(name, pretrain_seed(3 * k + 1), k)
