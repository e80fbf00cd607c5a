"""Reference programs of the f01 door tasks (OpenFridge, CloseCabinet) and the door predicates' thresholds.

Each program plays one pretrain episode in process (no images, no ledger) and must end with its task's
predicate holding on the simulator's state; the thresholds are checked in closed form on a compiled
scene: a door's normalised state is ``q / 1.57`` (range 0..1.57 rad), open at >= 0.90, closed at
<= 0.005.
"""

from __future__ import annotations

import mujoco
import pytest

from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.envs.kitchen import predicates as pr
from rle_tasks.envs.kitchen.fixture import DOOR_RANGE
from rle_tasks.envs.kitchen.harness.motion import Motion
from rle_tasks.envs.kitchen.harness.robot import Robot
from rle_tasks.envs.kitchen.sessions import KitchenScenes
from rle_tasks.f01_robocasa_speedrun.solutions.agents import Direct, solver
from rle_tasks.f01_robocasa_speedrun.task import KITCHEN_TASKS, KitchenTaskId, scenes

pytestmark = pytest.mark.physics

EPISODES = {"OpenFridge": (3, 3), "CloseCabinet": (4, 4)}
"""Task -> (pretrain kitchen, episode seed) of its program's episode (CloseCabinet 4: a fridge beside the hinge, which held
the door shut at reset before cabinet doors pivoted on their front face)."""


def _scenes(task: str) -> tuple[KitchenTaskId, KitchenScenes]:
    kitchen = next(k for k in KITCHEN_TASKS if k.task == task)
    return kitchen, scenes(kitchen, 3, Secret(PUBLIC_KEY, public=True), image_size=None)


def _play(task: str) -> tuple[float, bool, bool, int]:
    """(door's state at reset, solve's return, the task's predicate on the final state, actions) of one
    pretrain episode."""
    kitchen, sc = _scenes(task)
    session = sc.open_session(task_id=kitchen.task_id(3), budget=None)
    robot = Robot(Direct(session))
    k, seed = EPISODES[task]
    obs = robot.reset(kitchen=k, seed=seed)
    start = next(iter(obs["fixtures"][obs["target"]["fixture"]]["joints"].values()))
    steps0 = session.info()["steps_used"]
    ok = solver(task)(robot, Motion(robot))
    env = session.env
    f = env.scene.fixtures[env.scene.episode.target["fixture"]]
    pred = pr.is_open if task == "OpenFridge" else pr.is_closed
    return start, ok, pred(session.model, session.data, f), session.info()["steps_used"] - steps0


@pytest.mark.timeout(60)
@pytest.mark.parametrize("task", ["OpenFridge", "CloseCabinet"])
def test_program_solves_a_pretrain_episode(task: str) -> None:
    start, ok, holds, actions = _play(task)
    assert (start == 0.0) if task == "OpenFridge" else (0.9 <= start <= 1.0), start
    assert ok and holds, (task, ok, holds)
    assert actions < 400, actions


@pytest.mark.timeout(60)
def test_door_predicate_thresholds() -> None:
    """The predicates flip between 0.899 and 0.901 (open) and 0.0049 and 0.0051 (closed) of 1.57 rad."""
    assert DOOR_RANGE == (0.0, 1.57) and (pr.OPEN_AT, pr.CLOSED_AT) == (0.90, 0.005)
    for task, pred, cases in (
        ("OpenFridge", pr.is_open, ((0.899, False), (0.901, True))),
        ("CloseCabinet", pr.is_closed, ((0.0049, True), (0.0051, False))),
    ):
        k, seed = EPISODES[task]
        scene = _scenes(task)[1].scene(f"pretrain/{k}/{seed}").scene
        model = mujoco.MjModel.from_xml_string(scene.xml)
        data = mujoco.MjData(model)
        f = scene.fixtures[scene.episode.target["fixture"]]
        adr = model.jnt_qposadr[model.joint(f.joints[0]).id]
        for fraction, expected in cases:
            data.qpos[adr] = fraction * 1.57  # [rad]; normalised state = (q - 0) / (1.57 - 0)
            mujoco.mj_forward(model, data)
            assert pr.joint_fraction(model, data, f.joints[0]) == pytest.approx(fraction, rel=1e-12)
            assert pred(model, data, f) is expected, (task, fraction)
