"""Closed form of the two-pan balance of 03-balance-coins: tan(theta) = dm L_arm / (M_beam d)."""

import math

import mujoco
import numpy as np
import pytest

from rle_tasks.f03_physical_reasoning.balance import scene as bs

PARAMS = bs.BalanceParams()


def _scene(left: list[int], right: list[int], cubes: bs.CubeSet):
    """Balance at the origin, cube indices ``left``/``right`` resting on the pans, the rest on the floor."""
    spec = mujoco.MjSpec()
    spec.option.timestep = 0.002
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
    floor = spec.worldbody.add_geom()
    floor.type = mujoco.mjtGeom.mjGEOM_PLANE
    floor.size = np.array([1.0, 1.0, 0.1])
    bs.add_balance(spec, PARAMS, (0.0, 0.0, 0.0))
    top = PARAMS.pivot_height - PARAMS.hang_depth + cubes.size / 2 + 1e-4
    pos = np.array([[0.3 + 0.05 * i, 0.3, cubes.size / 2] for i in range(bs.N_CUBES)])
    for side, idx in ((-1.0, left), (1.0, right)):
        for k, i in enumerate(idx):
            pos[i] = (side * PARAMS.arm_length, PARAMS.tray_offset + (k - (len(idx) - 1) / 2) * 0.04, top)
    bs.add_cubes(spec, cubes, pos)
    model = spec.compile()
    return model, mujoco.MjData(model)


def test_beam_com_depth_is_derived_from_bar_and_bob():
    # Bar centred on the pivot, bob centred bob_depth below it: d = m_bob bob_depth / (m_bar + m_bob).
    model, _ = _scene([], [], bs.CubeSet())
    beam = model.body(bs.BEAM)
    d = PARAMS.bob_mass * PARAMS.bob_depth / (PARAMS.bar_mass + PARAMS.bob_mass)
    assert PARAMS.com_depth == pytest.approx(d, rel=1e-12)
    assert beam.mass[0] == pytest.approx(PARAMS.bar_mass + PARAMS.bob_mass, rel=1e-12)
    np.testing.assert_allclose(beam.ipos, [0.0, 0.0, -d], atol=1e-12)


@pytest.mark.physics
@pytest.mark.parametrize(
    ("left", "right", "heavy", "extra"),
    [
        ([0, 1, 2], [3, 4, 5], 1, 0.010),
        ([0, 1, 2], [3, 4, 5], 4, 0.008),
        ([0], [1], 0, 0.012),
        ([2], [6], 6, 0.006),
    ],
)
def test_settled_tilt_matches_the_closed_form(left, right, heavy, extra):
    # Moments about the pivot, pans hung on the beam axis line:
    #   dm g L_arm cos(theta) = M_beam g d sin(theta)  =>  tan(theta) = dm L_arm / (M_beam d),
    # dm = left load - right load; the beam hinge angle is q = -theta (left pan down for dm > 0).
    cubes = bs.CubeSet(heavy=heavy, heavy_extra=extra)
    model, data = _scene(left, right, cubes)
    masses = cubes.masses()
    dm = sum(masses[i] for i in left) - sum(masses[i] for i in right)
    for _ in range(250):  # cubes settle on the locked pans
        mujoco.mj_step(model, data)
    assert abs(bs.beam_angle(model, data)) < 2e-3  # the lock holds the beam level under the loads
    bs.release(model, data)
    for _ in range(2500):  # 5 s
        mujoco.mj_step(model, data)
    theta = -bs.beam_angle(model, data)
    expected = dm * PARAMS.arm_length / ((PARAMS.bar_mass + PARAMS.bob_mass) * PARAMS.com_depth)
    assert math.tan(theta) == pytest.approx(expected, rel=0.02)
    assert PARAMS.tilt(dm) == pytest.approx(math.atan(expected), rel=1e-12)
    assert abs(data.qvel[model.jnt_dofadr[model.joint(bs.BEAM_HINGE).id]]) < 1e-3  # settled


@pytest.mark.physics
def test_lock_holds_the_settled_angle():
    cubes = bs.CubeSet(heavy=0, heavy_extra=0.01)
    model, data = _scene([0], [1], cubes)
    bs.release(model, data)
    for _ in range(2000):
        mujoco.mj_step(model, data)
    settled = bs.beam_angle(model, data)
    assert bs.is_locked(model, data) is False
    bs.lock(model, data)
    assert bs.is_locked(model, data) is True
    for _ in range(500):
        mujoco.mj_step(model, data)
    assert bs.beam_angle(model, data) == pytest.approx(settled, abs=2e-3)
