"""Two objects of one category give two conditions of one wording; each keeps its own entry."""

from __future__ import annotations

import mujoco

from rle_tasks.envs.kitchen.env import KitchenEnv
from rle_tasks.envs.kitchen.scene import build_scene
from rle_tasks.envs.kitchen.sessions import pretrain_seed


def test_conditions_of_two_leftovers_of_one_category_stay_apart():
    scene = build_scene(pretrain_seed(0), "DumpLeftovers", 0)  # two breads in the bowl
    env = KitchenEnv(xml=scene.xml, scene=scene, level=3, image_size=None)
    names = env.conditions_names()
    assert names[:2] == ("bread out of the bowl", "bread out of the bowl (2)")
    model = env.build()
    data = mujoco.MjData(model)
    env.reset(model, data)
    mujoco.mj_forward(model, data)
    values = env.conditions(model, data)
    # one entry per condition: with merged names the dict held 3 of the 4, so a trial's m could not
    # exceed 3 and success was read from the second leftover alone
    assert tuple(values) == names
    assert not values[names[0]] and not values[names[1]]  # both leftovers start in the bowl
