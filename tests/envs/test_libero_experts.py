"""Scripted LIBERO experts and their demonstrations: geometry helpers in closed form, and one real
demonstration of LIBERO-10 task 0 built, verified and replayed across the process boundary."""

import json

import numpy as np
import pytest

from rle_tasks.envs.libero.demos import build_demos, verify_demos
from rle_tasks.envs.libero.expert_grasp import _hand_overlap
from rle_tasks.envs.libero.expert_motion import _axis_angle, _rotation, _rz


def test_axis_angle_of_known_rotations():
    # a rotation by theta about a unit axis k has the rotation vector theta k
    for theta in (0.3, 1.2, 3.0):
        assert np.allclose(_axis_angle(_rz(theta)), [0.0, 0.0, theta], atol=1e-9)
        k = np.array([1.0, 2.0, 2.0]) / 3.0
        assert np.allclose(_axis_angle(_rotation(k, theta)), theta * k, atol=1e-9)
    assert np.allclose(_axis_angle(np.eye(3)), 0.0)


def test_hand_footprint_overlap_in_closed_form():
    # hand centred at the origin, fingers along x: footprint [-0.11, 0.11] x [-0.035, 0.035]
    box = {"pos": np.zeros(3), "rot": np.eye(3)}
    tall = dict(box, box_lo=np.array([0.05, 0.0, 0.0]), box_hi=np.array([0.2, 0.1, 0.3]))
    # overlap (0.11 - 0.05) x (0.035 - 0.0) = 0.0021 m^2
    assert _hand_overlap(np.zeros(3), np.array([1.0, 0.0, 0.0]), 0.1, [tall]) == pytest.approx(0.0021)
    # fingers along y: footprint [-0.035, 0.035] x [-0.11, 0.11]: no overlap with x >= 0.05
    assert _hand_overlap(np.zeros(3), np.array([0.0, 1.0, 0.0]), 0.1, [tall]) == 0.0
    # an object whose top stays below the hand's lower face does not count
    low = dict(box, box_lo=np.array([0.05, 0.0, 0.0]), box_hi=np.array([0.2, 0.1, 0.05]))
    assert _hand_overlap(np.zeros(3), np.array([1.0, 0.0, 0.0]), 0.1, [low]) == 0.0


def test_demonstration_is_built_verified_and_replays(tmp_path, libero10_task0):
    """The expert solves LIBERO-10 task 0 from its first official initial state; the stored episode
    passes its checksum, an altered one is named, and replaying the stored actions in a fresh side
    process ends in the stored final state and in success."""
    lines = []
    manifest = build_demos(tmp_path, tasks=[0], per_task=1, seed=0, progress=lines.append)
    entry = manifest["tasks"]["0"]
    assert entry["attempts"][0]["success"] and entry["kept"] == 1, lines
    name = "task00_init00.npz"
    assert list(manifest["files"]) == [name] and verify_demos(tmp_path) == []
    ep = np.load(tmp_path / name)
    steps = len(ep["actions"])
    assert ep["state"].shape == (steps + 1, 8) and ep["sim_states"].shape[0] == steps + 1
    assert str(ep["language"]) == entry["language"] and steps < 520
    env = libero10_task0  # another side process than the builder's
    env.reset(0)
    success = False
    for a in ep["actions"]:
        _, success = env.step(a.astype(np.float64))
    final = env.sim_state()
    assert success
    np.testing.assert_allclose(final[1:], ep["sim_states"][-1][1:], atol=1e-6)
    # a second build finds the task complete and simulates nothing; an altered file is named
    again = build_demos(tmp_path, tasks=[0], per_task=1, seed=0, progress=lines.append)
    assert again == manifest and lines[-1] == "task 0: 1 episodes already built"
    data = dict(np.load(tmp_path / name))
    data["actions"] = data["actions"] + 0.01
    np.savez_compressed(tmp_path / name, **data)
    assert verify_demos(tmp_path) == [f"{name} was altered"]
    text = json.loads((tmp_path / "manifest.json").read_text())
    assert text["tasks"]["0"]["kept"] == 1


def test_a_recorded_episode_keeps_the_views_the_policy_saw(libero10_task0_rendered):
    """With a rendering environment the driver records both views live at every instant it records a
    state (what a policy is served); images rendered afterwards from the stored MuJoCo states differ,
    because an observation lags the stored state by part of a control step."""
    from rle_tasks.envs.libero.expert_motion import _Driver

    env = libero10_task0_rendered
    first = env.reset(0)
    d = _Driver(env, 10, first, record=True)
    for k in range(3):
        d.act(np.array([0.3, 0.0, -0.2 * k, 0.0, 0.0, 0.0, -1.0]))
    assert set(d.views) == {"agentview", "wrist"} and len(d.views["wrist"]) == 4 == len(d.sim_states)
    assert np.array_equal(d.views["agentview"][0], first["agentview"])
    rendered = env.render_states(np.array(d.sim_states))
    assert np.array_equal(rendered["agentview"][0], d.views["agentview"][0])  # at reset they agree
    lag = np.abs(rendered["state"][1:] - np.array(d.observations[1:])).max()
    assert 1e-4 < lag < 0.01  # [m, rad]: the stored state runs ahead of the observation


def test_skipped_views_change_neither_the_episode_nor_the_views_asked_for(libero10_task0_rendered):
    """Recording every 3rd frame's views (the other steps not rendered) gives, at frames 0, 3 and 6,
    the very images and states of a run that renders every step, and steps without views carry
    no images."""
    from rle_tasks.envs.libero.expert_motion import _Driver

    env = libero10_task0_rendered
    actions = [np.array([0.3, 0.1 * k, -0.2, 0.0, 0.0, 0.05, -1.0]) for k in range(6)]
    runs = []
    for every in (1, 3):
        d = _Driver(env, 10, env.reset(0), record=True, view_every=every)
        for a in actions:
            d.act(a)
        runs.append(d)
    full, sparse = runs
    assert sparse.view_frames == [0, 3, 6] and full.view_frames == list(range(7))
    for v in ("agentview", "wrist"):
        assert len(sparse.views[v]) == 3
        for k, frame in enumerate(sparse.view_frames):
            assert np.array_equal(sparse.views[v][k], full.views[v][frame])
    np.testing.assert_array_equal(np.array(sparse.sim_states)[:, 1:], np.array(full.sim_states)[:, 1:])
    obs, _ = env.step(actions[0], views=False)
    assert set(obs) == {"state"}


def test_a_stove_knob_is_no_door_and_task_2_is_offered(libero_side_env):
    """LIBERO-10 task 2 (turn on the stove, put the moka pot on it): the knob is hinged like the
    microwave's door, but it reaches 7.1 cm from its axis, under DOOR_MIN_REACH (15 cm; the door
    reaches 26.7 cm), so the cook region is not behind a door and the builder offers the task."""
    from rle_tasks.envs.libero import LiberoEnv
    from rle_tasks.envs.libero.expert_fixtures import DOOR_MIN_REACH, _door_front, _joint_of
    from rle_tasks.envs.libero.experts import supported

    with LiberoEnv("libero_10", 2, render=False) as env:
        env.start()
        sc = env.scene()
    knob = sc["joints"][_joint_of(sc, "flat_stove_1_cook_region")]
    corners = [
        [x, y]
        for x in (knob["part_lo"][0], knob["part_hi"][0])
        for y in (knob["part_lo"][1], knob["part_hi"][1])
    ]
    reach = max(float(np.linalg.norm(np.subtract(c, knob["anchor"][:2]))) for c in corners)
    assert knob["hinge"] and 0.05 < reach < DOOR_MIN_REACH
    assert _door_front(sc, "flat_stove_1_cook_region") is None and supported(sc)


def test_the_mug_goes_in_through_the_microwave_door_and_the_door_is_shut(libero_side_env):
    """LIBERO-10 task 9 (put the yellow and white mug in the microwave and close it), official state
    10: the expert sets the mug down in front of the opening, pinches its handle with the hand
    pointing through the opening, carries it in, backs out and swings the door shut, within the
    520-step horizon. The door's geometry is read exactly: closed along the microwave's x axis,
    reaching 26.7 cm, its outer face (with the handle) 6.4 cm off the hinge line; the opening faces
    the robot (-y)."""
    from rle_tasks.envs.libero import LiberoEnv
    from rle_tasks.envs.libero.expert_fixtures import _door_front, _leaf
    from rle_tasks.envs.libero.experts import run_expert, supported

    with LiberoEnv("libero_10", 9, render=False) as env:
        env.start()
        env.reset(10)
        sc = env.scene()
        closed, reach, thick = _leaf(sc, "microwave_1", "microwave_1_microjoint")
        assert (
            np.allclose(closed, [1.0, 0.0, 0.0]) and abs(reach - 0.267) < 0.001 and abs(thick - 0.064) < 0.001
        )
        assert np.allclose(_door_front(sc, "microwave_1_heating_region"), [0.0, -1.0, 0.0])
        assert sc["joints"]["microwave_1_microjoint"]["qpos"] < -1.3 and supported(sc)  # open
        res = run_expert(env, 10, np.random.default_rng([0, 9, 10]))
        end = env.scene()
    assert res.success and res.steps < 520, res.log
    placed = [line for line in res.log if "(through the door)" in line]
    assert len(placed) == 1 and placed[0].endswith("(in the target box)"), res.log
    assert end["joints"]["microwave_1_microjoint"]["qpos"] > -0.005  # LIBERO's closed range


def test_injected_noise_is_executed_while_the_expert_action_is_the_label(libero10_task0):
    """DART-style recording: the executed motion actions differ from the labels by the injected
    N(0, 0.2) (mean |difference| 0.2 sqrt(2/pi) = 0.16 where nothing is clipped), the gripper command
    is never perturbed, and replaying the executed actions reproduces the recorded final state."""
    from rle_tasks.envs.libero.experts import run_expert

    env = libero10_task0
    env.start()
    res = run_expert(env, 0, np.random.default_rng([0, 0, 0]), record=True, noise=0.2)
    assert res.executed is not None and res.executed.shape == res.actions.shape
    diff = res.executed - res.actions
    assert np.array_equal(diff[:, 6], np.zeros(len(diff)))
    inside = np.abs(res.actions[:, :6] + diff[:, :6]) < 1.0  # not clipped
    assert 0.13 < np.mean(np.abs(diff[:, :6][inside])) < 0.19
    env.reset(0)
    for a in res.executed:
        env.step(a)
    np.testing.assert_allclose(env.sim_state()[1:], res.sim_states[-1][1:], atol=1e-6)
