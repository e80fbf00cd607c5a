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


def _run(m, d, seconds, target_flange=None, magnet=0.0, at=None):
    """Run with the arm driven (servo targets ramped over 1 s) to a flange position pointing down;
    ``at = (t, fn)`` calls ``fn(model, data)`` once at the first control period from ``t`` [s]."""
    n = m.nbody and sum(1 for i in range(m.nbody) if m.body(i).name.startswith("bracket"))
    counter = EventCounter(m, n)
    logic = NestLogic(m, n)
    q_goal = np.array(HOME)
    done: list[float] = []
    if target_flange is not None:
        q_goal, err = ik_down(np.asarray(target_flange) - np.asarray(ROBOT_BASE), 0.0, np.array(HOME))
        assert err < 1e-3

    def control(model, data, t):
        s = min(t / 1.0, 1.0)
        data.ctrl[:7] = np.array(HOME) + s * (q_goal - np.array(HOME))
        data.ctrl[7] = magnet
        if at is not None and t >= at[0] and not done:
            at[1](model, data)
            done.append(t)
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


def _on_belt(x):
    return (x, BELT_Y, BELT_TOP + 0.001)


def test_a_part_the_nest_releases_alone_is_cleared_one_that_skips_it_is_not():
    """One bracket resting in the nest, one on the belt past the gate (where a part thrown over the
    gate lands). The nest holds its part ``NEST_DWELL_S``, opens, and the belt (v = BELT_SPEED) carries
    it to the end: cleared at NEST_DWELL_S + (BELT_X[1] - x_gate)/v, with x_gate in [0.28, 0.34] m (the
    part's centre against the gate), plus under 0.25 s to reach belt speed. The other reaches the end
    first and is not cleared: it never went through the nest."""
    from rle_tasks.f07_bin_clearing.public.env import NEST_DWELL_S

    m, d = _scene([_on_belt(NEST_X[0] + 0.06), _on_belt(BELT_X[1] - 0.15)])
    s = _run(m, d, 5.0)
    assert (s["delivered"], s["cleared"], s["not_through_nest"], s["blocked_nest"]) == (1, 1, 1, 0)
    (t,) = s["cleared_at_s"]
    assert NEST_DWELL_S + (BELT_X[1] - NEST_X[1]) / BELT_SPEED <= t
    assert t <= NEST_DWELL_S + (BELT_X[1] - 0.28) / BELT_SPEED + 0.25


def test_two_parts_dropped_together_block_the_nest_until_one_is_taken_out():
    """Two brackets in the nest: blocked, the gate stays shut and nothing is delivered; once one is
    taken out (here: lifted into the bin at t = 2 s) the other rests NEST_DWELL_S, is released alone and
    cleared."""
    m, d = _scene([_on_belt(NEST_X[0] + 0.035), _on_belt(NEST_X[0] + 0.1)])
    s = _run(m, d, 2.0)
    assert (s["blocked_nest"], s["delivered"], s["cleared"], s["not_through_nest"]) == (1, 0, 0, 0)

    def take_out(model, data):
        adr = model.jnt_qposadr[model.body(NAMES.part(1)).jntadr[0]]
        data.qpos[adr : adr + 3] = (0.5, 0.0, BIN_FLOOR_TOP + 0.03)
        data.qvel[model.jnt_dofadr[model.body(NAMES.part(1)).jntadr[0]] :][:6] = 0.0

    m, d = _scene([_on_belt(NEST_X[0] + 0.035), _on_belt(NEST_X[0] + 0.1)])
    s = _run(m, d, 7.0, at=(2.0, take_out))
    assert (s["blocked_nest"], s["delivered"], s["cleared"], s["not_through_nest"]) == (1, 1, 1, 0)
    assert s["cleared_at_s"][0] > 2.0 + 0.5


def test_two_parts_in_the_nest_block_it_and_a_part_past_the_guard_is_not_cleared():
    x0 = BELT_X[1] - 0.15
    m, d = _scene([(NEST_X[0] + 0.035, BELT_Y, BELT_TOP + 0.001), (NEST_X[0] + 0.1, BELT_Y, BELT_TOP + 0.001),
                   (x0, BELT_Y, BELT_TOP + 0.001)])  # fmt: skip
    s = _run(m, d, 3.0)
    assert s["blocked_nest"] == 1
    assert s["cleared"] == 0 and s["not_through_nest"] == 1  # the part past the guard skipped the nest
    assert s["makespan_s"] == 3.0  # incomplete: the episode's length
