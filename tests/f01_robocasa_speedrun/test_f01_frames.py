"""The programs' straightened frame (``agents.frame``): the run the robot starts facing becomes the
one-wall kitchen's wall (facing -y, back line y = 0), the observation stays one rigid motion of the
world's (base-frame entries unchanged), and a one-wall kitchen's observations pass through untouched."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from rle_tasks.envs.kitchen.env import KitchenEnv
from rle_tasks.envs.kitchen.layout_kinds import sample_layout
from rle_tasks.envs.kitchen.scene import scene_of
from rle_tasks.f01_robocasa_speedrun.solutions.agents.frame import Straightened, run_yaw


class _Fixed:
    """A client serving one observation."""

    def __init__(self, obs):
        self.obs = obs

    def reset(self, **_):
        return self.obs

    observe = step = reset


def _obs(kind: str, task: str, seed: int, level: int = 3):
    scene = scene_of(sample_layout(np.random.default_rng(seed), kind=kind), task, seed, seed)
    env = KitchenEnv(xml=scene.xml, scene=scene, level=level, image_size=(32, 32) if level == 2 else None)
    model = env.build()
    data = mujoco.MjData(model)
    env.reset(model, data)
    return scene, env.observe(model, data)


def test_run_yaw_snaps_the_start_heading_to_the_runs_quarter_turns():
    for yaw in (0.0, math.pi / 2, math.pi, 3 * math.pi / 2):
        for noise in (-0.05, 0.0, 0.05):
            got = run_yaw(math.remainder(yaw + math.pi / 2 + noise, 2 * math.pi))
            assert math.isclose(math.remainder(got - yaw, 2 * math.pi), 0.0, abs_tol=1e-12)
    assert run_yaw(math.pi / 2 + 0.04) == 0.0


def test_one_wall_observations_pass_through_untouched():
    _, obs = _obs("one_wall", "OpenFridge", 0)
    assert Straightened(_Fixed(obs)).reset() is obs


@pytest.mark.parametrize(
    ("kind", "task", "seed"), [("galley", "OpenFridge", 0), ("u_shaped", "TurnOnStove", 0)]
)
def test_a_turned_run_becomes_the_wall(kind, task, seed):
    scene, obs = _obs(kind, task, seed)
    target = scene.fixtures[scene.episode.target["fixture"]]
    assert abs(target.yaw) > 1.0, "the case must turn the frame"
    s = Straightened(_Fixed(obs)).reset()
    f = s["fixtures"][target.name]
    assert abs(f["yaw"]) < 1e-9 and np.allclose(f["facing"], [0.0, -1.0], atol=1e-9)
    run = [g for g in s["fixtures"].values() if abs(g["yaw"]) < 1e-9 and g["pos"][2] == 0.0]
    assert max(g["pos"][1] + g["size"][1] / 2 for g in run) == pytest.approx(0.0, abs=1e-9)  # back line
    # one rigid motion: base-frame entries unchanged and still consistent with the turned world entries
    c, sn = math.cos(s["base_yaw"]), math.sin(s["base_yaw"])
    local = np.array([[c, sn, 0.0], [-sn, c, 0.0], [0.0, 0.0, 1.0]]) @ (s["ee_pos"] - s["base_pos"])
    assert np.allclose(local, obs["ee_pos_base"], atol=1e-9)
    d_world = np.linalg.norm(obs["objects"]["obj"]["pos"] - obs["base_pos"]) if obs["objects"] else 0.0
    d_turned = np.linalg.norm(s["objects"]["obj"]["pos"] - s["base_pos"]) if s["objects"] else 0.0
    assert d_world == pytest.approx(d_turned, abs=1e-9)
    for name, g in obs["fixtures"].items():
        for role, p in g["sites"].items():
            assert np.linalg.norm(p - obs["base_pos"]) == pytest.approx(
                np.linalg.norm(s["fixtures"][name]["sites"][role] - s["base_pos"]), abs=1e-9
            )
