"""Closed forms of the sealed boxes of 03-hidden-com: centre of mass and edge-lift force."""

import mujoco
import numpy as np
import pytest

from rle_design.errors import ConfigError
from rle_tasks.f03_physical_reasoning.hidden_com.scene import QUADRANTS, BoxParams, add_box

G = 9.81


def _scene(params: BoxParams) -> tuple[mujoco.MjModel, mujoco.MjData]:
    spec = mujoco.MjSpec()
    spec.option.timestep = 0.001
    spec.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
    floor = spec.worldbody.add_geom()
    floor.type = mujoco.mjtGeom.mjGEOM_PLANE
    floor.size = np.array([1.0, 1.0, 0.1])
    add_box(spec, "box", params, (0.0, 0.0, 0.0))
    model = spec.compile()
    return model, mujoco.MjData(model)


@pytest.mark.parametrize("quadrant", QUADRANTS)
def test_com_and_mass_follow_the_ballast(quadrant):
    # r_c = m_b r_b / (m_s + m_b); m = m_s + m_b; the markings add no mass.
    params = BoxParams(quadrant=quadrant)
    model, _ = _scene(params)
    body = model.body("box")
    assert body.mass[0] == pytest.approx(params.shell_mass + params.ballast_mass, rel=1e-9)
    sx, sy = {"A": (1, 1), "B": (-1, 1), "C": (-1, -1), "D": (1, -1)}[quadrant]
    q = params.ballast_offset
    expected = params.ballast_mass * np.array([sx * q, sy * q, 0.0]) / params.mass
    np.testing.assert_allclose(body.ipos, expected, atol=1e-12)


def _edge_rise(params: BoxParams, force: float, axis: int, sign: float, seconds: float = 0.8) -> float:
    """Height [m] the lifted bottom edge gains under a vertical force ``force``.

    The force acts on the edge in the plane through the centre of mass normal to the edge (the planar
    closed form's plane); applied at the edge's midpoint instead, a ballast near that edge would tip
    the box about a corner first.
    """
    model, data = _scene(params)
    for _ in range(300):  # settle on the floor
        mujoco.mj_step(model, data)
    body = model.body("box").id
    local = np.zeros(3)
    local[axis] = sign * params.half[axis]
    local[1 - axis] = params.com[1 - axis]
    local[2] = -params.half[2]
    start = (data.xpos[body] + data.xmat[body].reshape(3, 3) @ local)[2]
    for _ in range(int(seconds / model.opt.timestep)):
        point = data.xpos[body] + data.xmat[body].reshape(3, 3) @ local
        data.qfrc_applied[:] = 0.0
        mujoco.mj_applyFT(
            model, data, np.array([0.0, 0.0, force]), np.zeros(3), point, body, data.qfrc_applied
        )
        mujoco.mj_step(model, data)
    point = data.xpos[body] + data.xmat[body].reshape(3, 3) @ local
    return float(point[2] - start)


@pytest.mark.physics
@pytest.mark.parametrize(("axis", "sign"), [(0, 1.0), (0, -1.0), (1, 1.0)])
def test_edge_lift_force_within_two_percent(axis, sign):
    # Moments about the pivot edge x_p = -sign*half: F (x_F - x_p) = m g (x_c - x_p), so
    # F = m g (x_c - x_p) / (x_F - x_p). At 0.98 F the edge stays down, at 1.02 F it rises.
    params = BoxParams(quadrant="A")
    x_f, x_p = sign * params.half[axis], -sign * params.half[axis]
    x_c = params.com[axis]
    f_star = params.mass * G * (x_c - x_p) / (x_f - x_p)
    assert params.edge_lift_force(axis, sign) == pytest.approx(f_star, rel=1e-12)
    assert _edge_rise(params, 0.98 * f_star, axis, sign) < 5e-4
    assert _edge_rise(params, 1.02 * f_star, axis, sign) > 3e-3


def test_heavy_side_needs_about_twice_the_lift_force():
    # Quadrant A (+x, +y), 0.4 kg at 18 mm: r_c = 0.4 * 0.018 / 0.6 = 0.012 m per axis; half width 0.035 m:
    # F(+x) = m g (0.012 + 0.035)/0.07, F(-x) = m g (0.035 - 0.012)/0.07, about 2 : 1.
    params = BoxParams(quadrant="A")
    heavy, light = params.edge_lift_force(0, 1.0), params.edge_lift_force(0, -1.0)
    assert heavy == pytest.approx(0.6 * G * 0.047 / 0.07, rel=1e-9)
    assert light == pytest.approx(0.6 * G * 0.023 / 0.07, rel=1e-9)


def test_bad_quadrant_is_refused():
    with pytest.raises(ConfigError, match="BoxParams.quadrant must be one of A, B, C, D, got 'E'") as err:
        BoxParams(quadrant="E")
    assert err.value.code == "f03.box_quadrant"
