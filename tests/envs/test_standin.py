"""The bimanual stand-in for RoboTwin 2.0: scene, servos, layouts, success predicates, scripted experts
and the robust track's looks."""

import mujoco
import numpy as np
import pytest

from rle_tasks.envs.standin import CLEAN, TASKS, StandinEnv, robust_look
from rle_tasks.envs.standin import tasks as T
from rle_tasks.envs.standin.env import HOME
from rle_tasks.envs.standin.experts import Expert, run_expert
from rle_tasks.envs.standin.scene import ARMS, finger_joint_names


def _hold(env: StandinEnv) -> np.ndarray:
    s = env.state
    return np.concatenate([s[0:6], [1.0], s[8:14], [1.0]])


def test_the_interface_is_the_cards_16_d_state_and_14_d_joint_targets():
    env = StandinEnv(0)
    obs = env.reset(0)
    assert obs["state"].shape == (16,) and obs["head"].shape == obs["front"].shape == (128, 128, 3)
    assert obs["head"].dtype == np.uint8
    np.testing.assert_allclose(obs["state"][0:6], HOME, atol=2e-3)
    np.testing.assert_allclose(obs["state"][6:8], (0.04, -0.04), atol=1e-3)  # fingers open
    assert env.model.nu == 16  # 2 x (6 joint servos + 2 finger servos)
    assert "state" in env.observe(views=False) and "head" not in env.observe(views=False)


def test_gravity_compensated_servos_hold_a_commanded_posture_without_steady_state_error():
    """A PD servo with exact gravity compensation settles where it is told: tau = kp (q* - q) - kv qdot
    and no other generalised force at rest, so q -> q* (steady-state error 0, up to the finger
    servos' coupling through contact, which is absent here)."""
    env = StandinEnv(0)
    env.reset(1)
    target = np.concatenate(
        [HOME + [0.2, -0.1, 0.15, -0.1, 0.1, 0.3], [1.0], HOME + [-0.2, 0.1, -0.1, 0.1, -0.1, -0.3], [1.0]]
    )
    for _ in range(20):  # 2 s
        env.step(target)
    s = env.state
    np.testing.assert_allclose(s[0:6], target[0:6], atol=2e-3)
    np.testing.assert_allclose(s[8:14], target[7:13], atol=2e-3)


def test_layouts_are_seeded_and_a_reset_restores_them():
    for t in range(len(TASKS)):
        assert T.layout(t, 5) == T.layout(t, 5) and T.layout(t, 5) != T.layout(t, 6)
    env = StandinEnv(2)
    env.reset(3)
    a = env.privileged()
    env.reset(4)
    env.reset(3)
    b = env.privileged()
    for k in a:
        np.testing.assert_allclose(a[k], b[k], atol=1e-9)  # a reset restores the layout exactly


def test_nothing_succeeds_at_reset():
    for t in range(len(TASKS)):
        env = StandinEnv(t)
        env.reset(0)
        assert not env.step(_hold(env)), TASKS[t].name


def _set_free(env, name, pos, quat=(1.0, 0.0, 0.0, 0.0)):
    m, d = env.model, env.data
    adr = m.jnt_qposadr[m.body_jntadr[m.body(name).id]]
    d.qpos[adr : adr + 3] = pos
    d.qpos[adr + 3 : adr + 7] = quat
    d.qvel[:] = 0
    mujoco.mj_forward(m, d)


def test_the_pot_counts_as_lifted_at_8_cm_and_within_20_degrees_of_upright():
    env = StandinEnv(0)
    env.reset(0)
    p0 = env._start["pot"].copy()
    _set_free(env, "pot", p0 + [0, 0, 0.079])
    assert not env.success()
    _set_free(env, "pot", p0 + [0, 0, 0.081])
    assert env.success()
    for deg, ok in ((19.0, True), (21.0, False)):  # tilt about x: body z makes deg with world z
        a = np.radians(deg)
        _set_free(env, "pot", p0 + [0, 0, 0.1], (np.cos(a / 2), np.sin(a / 2), 0.0, 0.0))
        assert env.success() is ok


def test_the_bar_counts_as_passed_only_in_the_right_gripper():
    env = StandinEnv(1)
    env.reset(0)
    p0 = env._start["bar"].copy()
    _set_free(env, "bar", [0.1, -0.2, p0[2] + 0.2])
    assert not env.success()  # in the air at the right place, but nobody holds it


def test_the_blocks_count_as_placed_only_inside_the_tray():
    env = StandinEnv(2)
    env.reset(0)
    tray = env.data.xpos[env.model.body("tray").id].copy()
    _set_free(env, "red", tray + [0.0, 0.04, 0.03])
    _set_free(env, "blue", tray + [0.0, -0.04, 0.03])
    assert env.success()
    _set_free(env, "blue", tray + [0.0, -0.04 - T.TRAY[1], 0.03])  # beyond the tray's side
    assert not env.success()


@pytest.mark.parametrize("task", range(len(TASKS)))
def test_the_scripted_expert_succeeds_on_seeded_starts(task):
    """The issue asks >= 80 % per task; the demonstration build records every attempt (manifest)."""
    env = StandinEnv(task)
    results = [run_expert(env, seed)[0] for seed in (100, 101, 102)]
    assert sum(results) >= 3 * 0.8, results


def test_the_expert_finishes_within_the_horizon_and_its_actions_are_the_protocols():
    for t in range(len(TASKS)):
        env = StandinEnv(t)
        env.reset(7)
        ex = Expert(env)
        actions = []
        while not ex.done:
            actions.append(ex.act())
        a = np.array(actions)
        assert a.shape[1] == 14 and len(a) <= TASKS[t].max_steps / 1.5
        assert set(np.unique(a[:, [6, 13]])) <= {0.0, 1.0}


def test_robust_looks_are_drawn_from_the_seed_and_keep_the_tasks_solvable():
    look = robust_look(1_234_567)
    assert look == robust_look(1_234_567) != robust_look(1_234_568) and look != CLEAN
    assert 2 <= len(look.clutter) <= 4 and abs(look.table_dz) <= 0.03
    for x, y, *_ in look.clutter:  # distractors stay off the work area
        assert x >= 0.28 or abs(y) >= 0.40
    clean = StandinEnv(2).reset(5)
    env = StandinEnv(2, look)
    perturbed = env.reset(5)
    assert np.abs(clean["head"].astype(int) - perturbed["head"]).mean() > 10  # it looks different
    assert run_expert(env, 5)[0]  # and the expert still solves it


def test_fingers_close_on_command():
    env = StandinEnv(0)
    env.reset(0)
    a = _hold(env)
    a[[6, 13]] = 0.0
    for _ in range(5):
        env.step(a)
    m, d = env.model, env.data
    for p in ARMS:
        q = [d.qpos[m.jnt_qposadr[m.joint(j).id]] for j in finger_joint_names(p)]
        assert abs(q[0]) < 2e-3 and abs(q[1]) < 2e-3
