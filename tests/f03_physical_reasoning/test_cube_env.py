"""03-pocket-cube: scrambles, the two-arm metered environment, its counters, rescue and reset."""

import math

import mujoco
import numpy as np
import pytest

from rle_design.control import TabletopEnv
from rle_design.ledger import MeteredSession
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.f03_physical_reasoning.cube import env as ce
from rle_tasks.f03_physical_reasoning.cube.reading import lowest_corner, poses_from_data
from rle_tasks.f03_physical_reasoning.cube.scene import (
    CUBE_CENTRE,
    MIN_DEPTH,
    PUBLIC_SCRAMBLES,
    STAND_TOP_Z,
    TABLE,
    CubeInstance,
    instance,
)
from rle_tasks.f03_physical_reasoning.cube.turns import classify

PUBLIC = Secret(PUBLIC_KEY, public=True)
INSTANCE = instance(PUBLIC)
HOLD = np.zeros(14)
HOLD[[6, 13]] = -1.0


@pytest.fixture(scope="module")
def env():
    return ce.make_env(INSTANCE, image_size=None)


def _fresh(env):
    model = env.build()
    env.prepare(model)
    data = mujoco.MjData(model)
    env.reset(model, data)
    return model, data


def test_public_scrambles_are_deep_enough_and_the_secret_draws_its_own():
    depths = [CubeInstance.from_moves(s).optimal for s in PUBLIC_SCRAMBLES]
    assert min(depths) >= MIN_DEPTH, depths
    assert CubeInstance.from_moves(PUBLIC_SCRAMBLES[0]) == INSTANCE
    drawn = [instance(Secret(bytes([k]) * 8, False)) for k in range(4)]
    assert drawn[0] == instance(Secret(bytes([0]) * 8, False))  # deterministic
    assert len({d.state for d in drawn}) == 4
    assert all(d.optimal >= MIN_DEPTH for d in drawn)


def test_action_layout_is_14_and_the_12d_tabletop_is_unchanged(env):
    model = env.build()
    assert env.action_size(model) == 14
    assert TabletopEnv(xml=env.xml, arms=("left/", "right/")).action_size(model) == 24
    with pytest.raises(ValueError, match="arm_action_size"):
        TabletopEnv(xml=env.xml, arm_action_size=9)


@pytest.mark.physics
def test_reset_shows_the_scramble_no_cube_pose_and_one_front_view():
    env = ce.make_env(INSTANCE)  # with images
    session = MeteredSession(env, task_id="03-pocket-cube", budget=10)
    obs = session.reset()
    assert ce.cube_reading(session.model, session.data).state == INSTANCE.state
    assert set(obs) == {"time", "arms", "rgb", "cube_session"}
    assert len(obs["arms"]) == 2 and set(obs["rgb"]) == {"front"}
    assert obs["rgb"]["front"].shape == (240, 320, 3)
    assert obs["cube_session"] == {"turns": 0, "unclassified": 0, "rescues": 0, "attempt_void": False}
    # the cube is in the image: the front view's centre region is not the background
    img = obs["rgb"]["front"].astype(float)
    assert img[100:140, 140:180].std() > 10.0


@pytest.mark.physics
def test_cube_rests_on_its_stand_on_the_lattice_while_both_arms_hold(env):
    model, data = _fresh(env)
    for _ in range(40):  # 2 s
        env.step(model, data, HOLD)
    poses = poses_from_data(model, data)
    reading = ce.cube_reading(model, data)
    assert reading.state == INSTANCE.state and math.degrees(reading.misalignment) < 2.0
    assert abs(lowest_corner(poses) - STAND_TOP_Z) < 1e-3
    assert ce.counters(model, data)["turns"] == 0


@pytest.mark.physics
def test_a_layer_turned_in_the_environment_is_counted_as_its_quarter_turn(env):
    """A couple on the top layer (the detent runs inside ``step``): one classified quarter turn."""
    model, data = _fresh(env)
    env.step(model, data, HOLD)
    bodies = ce._cube_ids(model)[1]
    top = data.xpos[bodies, 2] > data.xpos[model.body("cube").id, 2]
    before = ce.cube_reading(model, data).state
    for _ in range(40):
        data.xfrc_applied[bodies[top], 5] = 0.005
        data.xfrc_applied[bodies[~top], 5] = -0.005
        env.step(model, data, HOLD)
        reading = ce.cube_reading(model, data)
        if reading.state != before:  # past halfway: let the detent finish it
            break
    data.xfrc_applied[:] = 0.0
    for _ in range(20):
        env.step(model, data, HOLD)
    after = ce.cube_reading(model, data)
    assert math.degrees(after.misalignment) < 2.0
    move = classify(before, after.state)
    assert move is not None and not move.endswith("2")
    assert ce.counters(model, data) == {"turns": 1, "unclassified": 0, "rescues": 0, "attempt_void": False}


@pytest.mark.physics
def test_rescue_puts_a_dropped_cube_back_on_its_stand_keeping_its_state(env):
    model, data = _fresh(env)
    adr = model.jnt_qposadr[model.joint("cube_free").id]
    data.qpos[adr : adr + 3] = (0.12, 0.08, TABLE.top_z + 0.05)  # dropped beside the stand
    mujoco.mj_forward(model, data)
    for _ in range(30):
        env.step(model, data, HOLD)
    assert lowest_corner(poses_from_data(model, data)) - TABLE.top_z < 1e-3  # on the table
    kept = ce.cube_reading(model, data).state
    env.step(model, data, ce.rescue_action())
    for _ in range(20):
        env.step(model, data, HOLD)
    poses = poses_from_data(model, data)
    reading = ce.cube_reading(model, data)
    assert reading.state == kept == INSTANCE.state
    assert abs(lowest_corner(poses) - STAND_TOP_Z) < 1e-3
    assert np.allclose(poses.cubie_pos.mean(axis=0)[:2], CUBE_CENTRE[:2], atol=2e-3)
    assert ce.counters(model, data) == {"turns": 0, "unclassified": 0, "rescues": 1, "attempt_void": False}


@pytest.mark.physics
def test_a_reset_after_the_start_abandons_the_attempt(env):
    model, data = _fresh(env)
    assert not ce.counters(model, data)["attempt_void"]  # a reset at time 0 is the start
    env.step(model, data, HOLD)
    env.reset(model, data)
    assert ce.counters(model, data)["attempt_void"]
    assert ce.cube_reading(model, data).state == INSTANCE.state
    env.step(model, data, HOLD)
    env.reset(model, data)
    assert data.userdata[ce.VOID] == 2
