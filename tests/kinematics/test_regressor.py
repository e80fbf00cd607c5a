"""Gravity regressor, base parameters and D-optimal probe selection on a 7-joint chain."""

import mujoco
import numpy as np
import pinocchio as pin
import pytest

from rle_design.kinematics import (
    base_parameters,
    fit_base,
    gravity_parameters,
    gravity_regressor,
    greedy_d_optimal,
    information_logdet,
    model_from_mujoco,
)

# 7-joint chain with alternating axes (a Panda-like spherical shoulder and wrist)
_AXES = ["0 0 1", "0 1 0", "0 0 1", "0 -1 0", "0 0 1", "0 -1 0", "0 0 -1"]
_POS = ["0 0 0.05", "0 0 0.1", "0 0 0.17", "0.045 0 0.0", "-0.045 0 0.2", "0 0 0", "0.05 0 0"]


def _chain_xml() -> str:
    body = ""
    for i in reversed(range(7)):
        body = (
            f'<body name="l{i + 1}" pos="{_POS[i]}"><joint name="j{i + 1}" axis="{_AXES[i]}"/>'
            f'<inertial pos="0.01 {0.003 * i} 0.05" mass="{0.05 + 0.01 * i}" diaginertia="1e-4 1e-4 1e-4"/>'
            f"{body}</body>"
        )
    return f'<mujoco><compiler angle="radian"/><worldbody>{body}</worldbody></mujoco>'


@pytest.fixture(scope="module")
def km():
    return model_from_mujoco(mujoco.MjModel.from_xml_string(_chain_xml()))


def _scaled(km, scale: np.ndarray) -> np.ndarray:
    beta = gravity_parameters(km).copy()
    for j, s in enumerate(scale):
        beta[4 * j : 4 * j + 4] *= s  # scaling a link's mass scales its mass and first moment
    return beta


def test_regressor_times_parameters_is_the_gravity_torque(km):
    q = np.random.default_rng(0).uniform(-np.pi, np.pi, (10, 7))
    beta = gravity_parameters(km)
    for p in q:
        g = pin.computeGeneralizedGravity(km.model, km.data, p)
        assert np.max(np.abs(gravity_regressor(km, p) @ beta - g)) < 1e-12


def test_base_parameters_drop_the_unidentifiable_columns(km):
    bp = base_parameters(km)
    # joint 1 is vertical: its own link parameters never produce a torque (mass + first moment)
    assert set(range(4)) <= set(bp.zero.tolist())
    assert bp.size < 28
    q = np.random.default_rng(1).uniform(-np.pi, np.pi, (5, 7))
    beta = gravity_parameters(km)
    for p in q:
        y = gravity_regressor(km, p)
        assert np.allclose(bp.reduce(y) @ bp.project(beta), y @ beta, atol=1e-12)


def _probe_plan(km, bp, n: int = 15, seed: int = 3) -> np.ndarray:
    rng = np.random.default_rng(seed)
    cand = rng.uniform(-2.5, 2.5, (300, 7))
    regs = np.array([bp.reduce(gravity_regressor(km, c)) for c in cand])
    home = np.zeros(7)
    idx = greedy_d_optimal(regs, n, initial=bp.reduce(gravity_regressor(km, home))[None])
    return np.vstack([home, cand[idx]])


def test_sixteen_noiseless_probes_recover_injected_mass_scalings(km):
    bp = base_parameters(km)
    poses = _probe_plan(km, bp)
    assert poses.shape == (16, 7)
    true = _scaled(km, np.random.default_rng(4).uniform(0.85, 1.15, 7))
    y = np.vstack([bp.reduce(gravity_regressor(km, p)) for p in poses])
    tau = np.concatenate([gravity_regressor(km, p) @ true for p in poses])
    est = fit_base(y, tau)
    assert np.max(np.abs(est - bp.project(true))) < 1e-6
    test = np.random.default_rng(5).uniform(-np.pi, np.pi, (50, 7))
    err = max(
        np.max(np.abs(bp.reduce(gravity_regressor(km, p)) @ est - gravity_regressor(km, p) @ true))
        for p in test
    )
    assert err < 1e-6


def test_noise_degrades_the_fit_gracefully(km):
    """Torque prediction error grows about linearly with the probe noise (no blow-up)."""
    bp = base_parameters(km)
    poses = _probe_plan(km, bp)
    true = _scaled(km, np.full(7, 1.1))
    y = np.vstack([bp.reduce(gravity_regressor(km, p)) for p in poses])
    tau = np.concatenate([gravity_regressor(km, p) @ true for p in poses])
    test = np.random.default_rng(6).uniform(-np.pi, np.pi, (50, 7))
    errors = []
    for sigma in (1e-4, 1e-3, 1e-2):
        rng = np.random.default_rng(7)
        est = fit_base(y, tau + rng.normal(0, sigma, tau.shape))
        errors.append(
            max(
                np.max(np.abs(bp.reduce(gravity_regressor(km, p)) @ est - gravity_regressor(km, p) @ true))
                for p in test
            )
        )
    assert errors[0] < errors[1] < errors[2] < 10 * 1e-2  # prediction error below 10x the noise
    assert 3 < errors[2] / errors[1] < 30


def test_greedy_d_optimal_beats_random_probes(km):
    bp = base_parameters(km)
    rng = np.random.default_rng(8)
    cand = rng.uniform(-2.5, 2.5, (300, 7))
    regs = np.array([bp.reduce(gravity_regressor(km, c)) for c in cand])
    chosen = greedy_d_optimal(regs, 15)
    assert len(set(chosen.tolist())) == 15
    random_sets = [information_logdet(regs[rng.choice(300, 15, replace=False)]) for _ in range(20)]
    assert information_logdet(regs[chosen]) > max(random_sets)
