"""Activity groups as data, and the stage report's s_trial on hand-built kitchen states."""

import mujoco
import numpy as np
import pytest

from rle_tasks.envs.kitchen.composite_tasks import COMPOSITES
from rle_tasks.envs.kitchen.env import KitchenEnv
from rle_tasks.envs.kitchen.scene import build_scene
from rle_tasks.f02_harness_transfer.groups import GROUPS, SKILLS
from rle_tasks.f02_harness_transfer.transfer import stage_score


def test_fifteen_groups_five_per_difficulty_each_covering_its_held_out_task():
    assert [g.number for g in GROUPS] == list(range(1, 16))
    for level in ("easy", "medium", "hard"):
        assert sum(g.difficulty == level for g in GROUPS) == 5
    for g in GROUPS:
        assert g.covered() and g.held_out not in g.develop
        assert set(SKILLS[g.held_out]) - {"navigate"} <= {s for t in g.develop for s in SKILLS[t]}
    assert set(SKILLS) == set(COMPOSITES)


@pytest.mark.parametrize(
    "b,m,n,success,recorded,expected",
    [(1, 3, 4, False, True, 2 / 3), (1, 1, 4, False, True, 0.0), (0, 2, 2, True, True, 1.0), (2, 2, 2, False, True, 0.0),
     (0, 1, 2, False, False, 0.0), (2, 1, 4, False, True, 0.0), (0, 0, 3, True, True, 1.0)],
)  # fmt: skip
def test_s_trial_formula(b, m, n, success, recorded, expected):
    """s = 1 on success; 0 without records or n = b; else clip((m - b) / (n - b), 0, 1)."""
    assert stage_score(b, m, n, success, recorded) == pytest.approx(expected)


def _set_free(model, data, body: str, pos) -> None:
    adr = model.jnt_qposadr[model.joint(body).id]
    data.qpos[adr : adr + 3] = pos
    data.qpos[adr + 3 : adr + 7] = (1, 0, 0, 0)
    data.qvel[model.jnt_dofadr[model.joint(body).id] : model.jnt_dofadr[model.joint(body).id] + 6] = 0


def test_stage_report_on_hand_built_states_of_serve_from_drawer():
    """ServeFromDrawer: conjuncts (fruit in the plate, drawer closed, gripper far). Start: fruit in the open
    drawer, gripper far: b = 1. Fruit set onto the plate: 2 of 3. Drawer then closed too: 3 of 3 = success.
    s_trial at the middle state: (2 - 1) / (3 - 1) = 0.5."""
    scene = build_scene(1_000_011, "ServeFromDrawer", 4)
    env = KitchenEnv(xml=scene.xml, scene=scene, level=2, image_size=None)
    model = env.build()
    data = mujoco.MjData(model)
    env.reset(model, data)
    start = env.conditions(model, data)
    assert list(start.values()) == [False, False, True]
    b = sum(start.values())
    plate = data.xpos[model.body("plate").id].copy()
    _set_free(model, data, "fruit", plate + np.array([0.0, 0.0, 0.03]))
    for _ in range(200):
        mujoco.mj_step(model, data)
    middle = env.conditions(model, data)
    assert list(middle.values()) == [True, False, True]
    drawer = scene.fixtures[scene.episode.target["drawer"]]
    data.qpos[model.jnt_qposadr[model.joint(drawer.joints[0]).id]] = 0.0
    mujoco.mj_forward(model, data)
    end = env.conditions(model, data)
    assert all(end.values()) and env.success(model, data)
    m = max(sum(v.values()) for v in (start, middle))
    assert stage_score(b, m, 3, False, True) == pytest.approx(0.5)
    assert stage_score(b, 3, 3, True, True) == 1.0
