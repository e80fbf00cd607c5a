"""Operational-space controller, 12-D action layout, Cartesian helper and ledger replay."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from rle_design.control import (
    ACTION_SIZE,
    POS_STEP,
    ArmGroup,
    CartesianHelper,
    ReplayError,
    TabletopEnv,
    orientation_error,
    replay,
)
from rle_design.ledger import MeteredSession, verify_ledger
from rle_design.scene.tabletop import TabletopConfig, add_free_box, build_tabletop, finish

POS_TOL = 1e-3
"""Controller convergence tolerance on position [m]."""
ROT_TOL = 1e-2
"""Controller convergence tolerance on orientation [rad]."""


@pytest.fixture(scope="module")
def scene() -> tuple[TabletopEnv, mujoco.MjModel]:
    spec = build_tabletop(TabletopConfig())
    add_free_box(spec, "block", (0.02, 0.02, 0.02), (0.3, 0.2, 0.77), mass=0.1)
    finish(spec)
    env = TabletopEnv(xml=spec.to_xml(), n_substeps=10, image_size=None, privileged=True)
    model = env.build()
    env.prepare(model)
    return env, model


def _reset(env: TabletopEnv, model: mujoco.MjModel) -> mujoco.MjData:
    data = mujoco.MjData(model)
    env.reset(model, data)
    return data


def test_orientation_error_is_the_rotation_vector() -> None:
    axis = np.array([1.0, 2.0, -0.5]) / np.linalg.norm([1.0, 2.0, -0.5])
    angle = 0.3
    q_rot = np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * axis])
    q0 = np.array([0.0, 0.7071067811865476, 0.7071067811865476, 0.0])
    q1 = np.zeros(4)
    mujoco.mju_mulQuat(q1, q_rot, q0)  # world-frame rotation of q0
    np.testing.assert_allclose(orientation_error(q1, q0), angle * axis, atol=1e-12)


def test_osc_converges_to_a_target_pose(scene: tuple[TabletopEnv, mujoco.MjModel]) -> None:
    env, model = scene
    data = _reset(env, model)
    mocap = model.body("panda/target").mocapid[0]
    goal = data.mocap_pos[mocap] + np.array([0.06, -0.07, -0.08])  # within the leash
    turn = np.array([np.cos(0.2), 0.0, 0.0, np.sin(0.2)])  # 0.4 rad about world z
    goal_q = np.zeros(4)
    mujoco.mju_mulQuat(goal_q, turn, data.mocap_quat[mocap].copy())
    data.mocap_pos[mocap], data.mocap_quat[mocap] = goal, goal_q
    hold = np.zeros(ACTION_SIZE)
    hold[6] = -1.0
    for _ in range(40):  # 2 s
        env.step(model, data, hold)
    site = model.site("panda/hand/grip_site").id
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, data.site_xmat[site])
    assert np.linalg.norm(data.site_xpos[site] - goal) < POS_TOL
    assert np.linalg.norm(orientation_error(goal_q, quat)) < ROT_TOL


def test_action_moves_the_target_by_the_scaled_delta_in_the_base_frame(
    scene: tuple[TabletopEnv, mujoco.MjModel],
) -> None:
    env, model = scene
    data = _reset(env, model)
    mocap = model.body("panda/target").mocapid[0]
    before = data.mocap_pos[mocap].copy()
    action = np.zeros(ACTION_SIZE)
    action[0], action[2], action[7:] = 0.5, -1.0, 1.0  # base/torso/mode inert
    env.step(model, data, action)
    np.testing.assert_allclose(data.mocap_pos[mocap] - before, [0.5 * POS_STEP, 0.0, -POS_STEP], atol=1e-12)


def test_helper_issues_only_ordinary_actions(scene: tuple[TabletopEnv, mujoco.MjModel]) -> None:
    env, model = scene
    data = _reset(env, model)
    sent: list[np.ndarray] = []

    def step(action: np.ndarray) -> dict:
        sent.append(np.array(action, dtype=float))
        env.step(model, data, action)
        return env.observe(model, data)

    helper = CartesianHelper(step, env.observe(model, data))
    goal = np.array([0.3, 0.2, 0.79])
    result = helper.move_to(goal + [0.0, 0.0, 0.1])
    assert result.reached
    assert helper.move_to(goal).reached
    helper.grasp()
    lifted = helper.move_to(goal + [0.0, 0.0, 0.1])
    assert lifted.reached and lifted.pos_error < 2e-3
    assert data.qpos[model.jnt_qposadr[model.joint("block").id] + 2] > 0.84  # the block came along
    assert len(sent) == helper.steps
    arr = np.array(sent)
    assert arr.shape == (helper.steps, ACTION_SIZE)
    assert np.isfinite(arr).all() and np.abs(arr).max() <= 1.0
    assert not arr[:, 7:].any()  # base, torso, mode never used by a fixed arm


def test_a_new_helper_keeps_the_grasp_and_move_to_warns_when_it_cannot_reach(
    scene: tuple[TabletopEnv, mujoco.MjModel],
) -> None:
    """A helper made while the gripper holds a block keeps it closed (``gripper_command`` +1); a goal
    out of reach ends with a warning and ``reached`` False."""
    env, model = scene
    data = _reset(env, model)
    assert env.observe(model, data)["arms"][0]["gripper_command"] == -1.0  # reset: open

    def step(action: np.ndarray) -> dict:
        env.step(model, data, action)
        return env.observe(model, data)

    first = CartesianHelper(step, env.observe(model, data))
    goal = np.array([0.3, 0.2, 0.79])
    assert first.move_to(goal + [0.0, 0.0, 0.1]).reached and first.move_to(goal).reached
    first.grasp()
    second = CartesianHelper(step, env.observe(model, data))
    assert second.grip == 1.0
    assert second.move_to(goal + [0.0, 0.0, 0.1]).reached
    assert data.qpos[model.jnt_qposadr[model.joint("block").id] + 2] > 0.84  # still held
    with pytest.warns(RuntimeWarning, match="move_to used its 30 actions"):
        far = second.move_to(np.array([2.0, 0.0, 0.9]), max_steps=30)  # 2 m away: out of reach
    assert not far.reached and far.steps == 30


def test_metered_session_replays_to_the_same_final_state(
    scene: tuple[TabletopEnv, mujoco.MjModel], tmp_path
) -> None:
    env, _ = scene
    key = b"k" * 32
    session = MeteredSession(
        env, task_id="test-tabletop", budget=200, key=key, ledger_path=tmp_path / "l.jsonl"
    )
    obs = session.reset()
    helper = CartesianHelper(session.step, obs)
    helper.move_to(np.array([0.3, 0.2, 0.85]), max_steps=30)
    session.reset()
    helper.obs = session.observe()
    helper.move_to(np.array([0.2, -0.1, 0.9]), max_steps=25)
    session.seal()
    assert session.steps_used == 2 + helper.steps
    assert verify_ledger(tmp_path / "l.jsonl", key, "test-tabletop").valid
    _, data, n = replay(env, tmp_path / "l.jsonl")
    assert n == helper.steps
    np.testing.assert_array_equal(data.qpos, session.data.qpos)
    other = TabletopEnv(xml=env.xml.replace("tabletop", "tabletop2", 1), n_substeps=10, image_size=None)
    with pytest.raises(ReplayError, match="recorded on scene"):
        replay(other, tmp_path / "l.jsonl")


def test_wrong_action_size_is_refused_without_charge(scene: tuple[TabletopEnv, mujoco.MjModel]) -> None:
    env, _ = scene
    session = MeteredSession(env, task_id="t", budget=5)
    with pytest.raises(Exception, match=r"action must be 12 real numbers \(the environment's action\)"):
        session.step(np.zeros(9))
    assert session.steps_used == 0


def test_replay_on_a_different_control_period_is_refused(
    scene: tuple[TabletopEnv, mujoco.MjModel], tmp_path
) -> None:
    env, _ = scene
    key = b"k" * 32
    session = MeteredSession(env, task_id="t", budget=20, key=key, ledger_path=tmp_path / "l.jsonl")
    session.reset()
    for _ in range(3):
        session.step(np.zeros(ACTION_SIZE))
    session.seal()
    slower = TabletopEnv(xml=env.xml, n_substeps=5, image_size=None)  # same scene, other control period
    with pytest.raises(ReplayError, match="differs from the recorded") as info:
        replay(slower, tmp_path / "l.jsonl")
    assert info.value.code == "replay.diverged"


def test_arm_group_keeps_the_other_arms_grip() -> None:
    """While one arm moves, its actions hold the other arm's gripper command (a held part stays held)."""
    obs = {"arms": [{}, {}]}
    sent: list[np.ndarray] = []

    def step(action: np.ndarray) -> dict:
        sent.append(np.array(action))
        return obs

    group = ArmGroup(step, obs, n_arms=2, arm_size=7)
    group.arm(0).set_gripper(-0.4, 2)
    group.arm(1).set_gripper(0.5, 2)
    group.arm(1).wait(1)
    assert [a[6] for a in sent] == [-0.4] * 5  # arm 0's gripper entry
    assert [a[13] for a in sent] == [-1.0, -1.0, 0.5, 0.5, 0.5]  # arm 1: open until it closed part way
    assert all(not a[0:6].any() and not a[7:13].any() for a in sent)  # no arm moved
