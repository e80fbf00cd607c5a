"""Every event type triggered by a scripted scenario (no policy): floor, damage, bin, blocked, cleared."""

import mujoco
import numpy as np
import pytest

from rle_design.rollout import run_episode
from rle_tasks.f07_bin_clearing.public.env import NestLogic
from rle_tasks.f07_bin_clearing.public.events import PART_IMPACT_N, EventCounter
from rle_tasks.f07_bin_clearing.public.pile import arm_qpos_adr
from rle_tasks.f07_bin_clearing.public.workcell import (
    BELT_SPEED,
    BELT_TOP,
    BELT_X,
    BELT_Y,
    BIN_FLOOR_TOP,
    HOME,
    NAMES,
    NEST_X,
    ROBOT_BASE,
    TOOL_LENGTH,
    build_workcell,
)
from rle_tasks.f07_bin_clearing.solutions.reference.policy.kinematics import ik_down

pytestmark = pytest.mark.physics


UP, DOWN = (1, 0, 0, 0), (0, 1, 0, 0)  # flanges up; flanges down (web on top)


def _scene(parts, quats=None):
    m = build_workcell(len(parts)).compile()
    d = mujoco.MjData(m)
    d.qpos[arm_qpos_adr(m)] = HOME
    d.ctrl[:7] = HOME
    for i, p in enumerate(parts):
        adr = m.jnt_qposadr[m.body(NAMES.part(i)).jntadr[0]]
        d.qpos[adr : adr + 3] = p
        d.qpos[adr + 3 : adr + 7] = UP if quats is None else quats[i]
    mujoco.mj_forward(m, d)
    return m, d


def _run(m, d, seconds, target_flange=None, magnet=0.0):
    """Run with the arm driven (servo targets ramped over 1 s) to a flange position pointing down."""
    n = m.nbody and sum(1 for i in range(m.nbody) if m.body(i).name.startswith("bracket"))
    counter = EventCounter(m, n)
    logic = NestLogic(m, n)
    q_goal = np.array(HOME)
    if target_flange is not None:
        q_goal, err = ik_down(np.asarray(target_flange) - np.asarray(ROBOT_BASE), 0.0, np.array(HOME))
        assert err < 1e-3

    def control(model, data, t):
        s = min(t / 1.0, 1.0)
        data.ctrl[:7] = np.array(HOME) + s * (q_goal - np.array(HOME))
        data.ctrl[7] = magnet
        if t > 0:
            logic.update(model, data)

    run_episode(m, d, int(seconds / m.opt.timestep), control=control, control_every=25, terms=[counter])
    return counter.counts.summary(n, seconds)


def test_part_dropped_beside_the_bin_is_a_floor_event():
    m, d = _scene([(0.45, -0.26, 0.30), (0.5, 0.0, BIN_FLOOR_TOP + 0.001)])
    s = _run(m, d, 1.0)
    assert s["N_floor"] == 1 and s["N_damage"] == 0 and s["N_bin"] == 0


def test_pad_driven_into_the_bin_floor_is_a_bin_impact():
    m, d = _scene([(0.8, BELT_Y, BELT_TOP + 0.001)])
    # the stem's end (TOOL_LENGTH - 10 mm pad) pushed 20 mm below the bin floor at the bin's centre
    s = _run(m, d, 2.0, (0.5, 0.05, BIN_FLOOR_TOP + TOOL_LENGTH - 0.01 - 0.02))
    assert s["N_bin"] >= 1 and s["peak_bin_force_N"] > 40.0


def test_pad_crushing_a_part_is_damage():
    # a bracket standing on its flanges (web 30 mm up); the pad commanded 100 mm below the web, magnet on
    m, d = _scene([(0.5, 0.05, BIN_FLOOR_TOP + 0.0305)], [DOWN])
    s = _run(m, d, 2.0, (0.5, 0.05, BIN_FLOOR_TOP + 0.03 + TOOL_LENGTH - 0.10), magnet=1.0)
    assert s["damaged_parts"] == [0] and s["peak_part_force_N"] > PART_IMPACT_N
    assert s["N_damage"] >= 1


def test_free_drop_of_a_part_is_no_damage():
    m, d = _scene([(0.5, 0.0, BIN_FLOOR_TOP + 2.0)])  # 2 m, eight times the highest dump height
    s = _run(m, d, 2.0)
    assert s["N_damage"] == 0 and s["peak_part_force_N"] < PART_IMPACT_N


def test_pad_driven_into_the_belt_is_robot_damage():
    m, d = _scene([(0.5, 0.0, BIN_FLOOR_TOP + 0.001)])
    s = _run(m, d, 2.0, (0.60, BELT_Y, BELT_TOP + TOOL_LENGTH - 0.01 - 0.02))
    assert s["robot_impacts"] >= 1 and s["N_bin"] == 0


def test_two_parts_in_the_nest_block_it_and_one_part_is_cleared_at_belt_speed():
    x0 = BELT_X[1] - 0.15
    m, d = _scene([(NEST_X[0] + 0.035, BELT_Y, BELT_TOP + 0.001), (NEST_X[0] + 0.1, BELT_Y, BELT_TOP + 0.001),
                   (x0, BELT_Y, BELT_TOP + 0.001)])  # fmt: skip
    s = _run(m, d, 3.0)
    assert s["blocked_nest"] == 1
    assert s["cleared"] == 1  # only the part already past the guard
    # the centre crosses the belt's end after (0.15 m) / v, plus under 0.25 s to reach belt speed
    assert 0.15 / BELT_SPEED <= s["cleared_at_s"][0] <= 0.15 / BELT_SPEED + 0.25
    assert s["makespan_s"] == 3.0  # incomplete: the episode's length
