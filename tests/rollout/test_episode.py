"""The episode loop, its terms and environment definitions, against closed forms and the ledger."""

import math

import mujoco
import numpy as np
import pytest

from rle_design.ledger import MeteredEnv, MeteredSession
from rle_design.rollout import (
    ContactBetween,
    EnvDefinition,
    HoldAtTarget,
    RolloutError,
    SimulationWarnings,
    TiltLimit,
    run_episode,
)
from rle_design.rollout.env import ActionError
from rle_design.rollout.terms import Event, Term

SLIDER = """
<mujoco>
  <option timestep="0.001" gravity="0 0 0" integrator="Euler"/>
  <worldbody>
    <body name="cart">
      <joint name="x" type="slide" axis="1 0 0"/>
      <geom name="cart" type="box" size="0.1 0.1 0.1" mass="2"/>
      <site name="tip" pos="0 0 0"/>
    </body>
  </worldbody>
  <actuator><motor name="push" joint="x" ctrlrange="-100 100"/></actuator>
</mujoco>
"""


def _slider():
    m = mujoco.MjModel.from_xml_string(SLIDER)
    return m, mujoco.MjData(m)


class _Count(Term):
    name = "count"

    def __init__(self, every):
        self.every, self.steps = every, []

    def update(self, model, data, t):
        self.steps.append(round(data.time / model.opt.timestep))
        return None


def test_constant_force_matches_uniform_acceleration():
    # F = m a on a frictionless slider: x(t) = F t^2 / (2 m) (semi-implicit Euler: F dt^2 n (n+1) / (2 m))
    m, d = _slider()
    n, force, mass, dt = 400, 3.0, 2.0, 0.001

    def control(model, data, t):
        data.ctrl[0] = force

    ep = run_episode(m, d, n, control=control, control_every=10)
    assert ep.steps == n and ep.end is None
    assert d.qpos[0] == pytest.approx(force * dt**2 * n * (n + 1) / (2 * mass), rel=1e-12)
    assert d.qpos[0] == pytest.approx(force * (n * dt) ** 2 / (2 * mass), rel=5e-3)


def test_chunks_in_c_give_the_same_state_as_a_python_step_loop():
    m, d1 = _slider()
    d2 = mujoco.MjData(m)
    calls = []

    def control(model, data, t):
        calls.append(t)
        data.ctrl[0] = math.sin(7 * t)

    run_episode(m, d1, 250, control=control, control_every=10, terms=[_Count(25)])
    for k in range(250):
        if k % 10 == 0:
            d2.ctrl[0] = math.sin(7 * d2.time)
        mujoco.mj_step(m, d2)
    assert d1.qpos[0] == d2.qpos[0] and d1.qvel[0] == d2.qvel[0]
    assert len(calls) == 25 and calls[1] == pytest.approx(0.01)


@pytest.mark.parametrize("term_every", [25, 1])
def test_prepare_runs_one_step_before_each_later_control_call_and_changes_no_physics(term_every):
    # 250 steps, control every 10: calls at steps 0, 10, ..., 240 (25); prepare before the calls
    # at 10..240 (24), each time with the physics one step short of the boundary. A term due every
    # step (term_every = 1) makes the loop step one by one, and prepare keeps its place.
    m, d1 = _slider()
    d2 = mujoco.MjData(m)
    seen = []

    def control(model, data, t):
        data.ctrl[0] = math.sin(7 * t)

    def prepare():
        seen.append(round(d1.time / m.opt.timestep))

    run_episode(m, d1, 250, control=control, control_every=10, terms=[_Count(term_every)], prepare=prepare)
    run_episode(m, d2, 250, control=control, control_every=10, terms=[_Count(term_every)])
    assert seen == [10 * k - 1 for k in range(1, 25)]
    assert d1.qpos[0] == d2.qpos[0] and d1.qvel[0] == d2.qvel[0]


def test_terms_run_at_their_period_and_final_terms_after_the_last_step():
    m, d = _slider()
    every5, final = _Count(5), _Count(4)
    final.final = True
    run_episode(m, d, 18, terms=[every5, final])
    assert every5.steps == [5, 10, 15]
    assert final.steps == [4, 8, 12, 16, 18]


def test_first_ending_event_in_term_order_ends_the_episode_after_all_terms_ran():
    m, d = _slider()

    class Fail(Term):
        name, every = "fail", 3

        def update(self, model, data, t):
            return Event("fail", "fail", "stop", t)

    seen = _Count(3)
    ep = run_episode(m, d, 30, terms=[Fail(), seen])
    assert ep.steps == 3 and seen.steps == [3] and ep.end.message == "stop" and not ep.success


def test_bad_periods_are_refused():
    m, d = _slider()
    with pytest.raises(RolloutError, match=r"positive integers, got \[0\]"):
        run_episode(m, d, 10, control_every=0)


def test_hold_at_target_succeeds_after_the_hold_time():
    m, d = _slider()
    hold = HoldAtTarget(0, np.zeros(3), tolerance=0.01, hold_s=0.05, every=10, period=0.01)
    ep = run_episode(m, d, 1000, terms=[hold])
    # the cart rests on the target: success at the fifth evaluation (5 x 10 ms = hold time)
    assert ep.success and ep.steps == 50 and hold.best == 0.0


def test_tilt_limit_on_a_falling_pendulum():
    xml = """
    <mujoco><option timestep="0.001"/>
      <worldbody><body name="rod" euler="0 2 0"><joint type="hinge" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0 0 0.5" size="0.02" mass="1"/></body></worldbody>
    </mujoco>"""
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    tilt = TiltLimit(1, max_deg=10.0, every=5, what="rod tilt")
    ep = run_episode(m, d, 2000, terms=[tilt])
    # the rod starts 2 deg from vertical: it falls past 10 deg, which ends the episode
    assert ep.end.term == "tilt" and ep.end.message.startswith("tipping: rod tilt ")
    assert 10.0 < tilt.peak_deg < 12.0


def test_contact_between_names_the_pair():
    xml = """
    <mujoco><option timestep="0.002"/>
      <worldbody><geom name="floor" type="plane" size="1 1 0.1"/>
        <body name="ball" pos="0 0 0.3"><freejoint/><geom name="ball" type="sphere" size="0.05"/></body>
      </worldbody></mujoco>"""
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    ep = run_episode(m, d, 1000, terms=[ContactBetween(m.ngeom, [1], [0], every=1, what="impact")])
    # free fall from h = 0.25 m (ball bottom) takes sqrt(2 h / g) = 0.226 s
    assert ep.end.message.startswith("impact: floor touched ball at t = ")
    assert ep.time == pytest.approx(math.sqrt(2 * 0.25 / 9.81), abs=0.01)


def test_simulation_warnings_fail_with_the_warning_name():
    m, d = _slider()
    d.qvel[0] = 1e12  # beyond MuJoCo's 1e10 bound: mjWARN_BADQVEL and a reset
    ep = run_episode(m, d, 5, terms=[SimulationWarnings()])
    assert ep.end.term == "warning" and "mjWARN_BADQVEL" in ep.end.message


class _Env(EnvDefinition):
    n_substeps = 5

    def build(self):
        return mujoco.MjModel.from_xml_string(SLIDER)


def test_metered_session_and_evaluation_episode_drive_the_scene_alike(tmp_path):
    actions = [np.array([a]) for a in (1.0, -2.0, 0.5, 3.0)]
    env = MeteredEnv(SLIDER, n_substeps=5)
    session = MeteredSession(env, task_id="00-test", budget=None)
    session.reset()
    for a in actions:
        obs = session.step(a)
    m = env.build()
    d = mujoco.MjData(m)
    env.reset(m, d)
    it = iter(actions)
    ep = env.episode(m, d, lambda o: next(it), n_actions=len(actions))
    assert ep.steps == 20
    assert d.qpos[0] == obs["qpos"][0] and d.qvel[0] == obs["qvel"][0]


def test_invalid_actions_are_participant_faults():
    env = _Env()
    m = env.build()
    with pytest.raises(
        ActionError, match=r"action must be 1 real numbers \(the actuators' ctrl\), got shape «\(2,\)»"
    ):
        env.action(m, [1.0, 2.0])
    with pytest.raises(ActionError, match="NaN or infinity"):
        env.action(m, [float("nan")])
