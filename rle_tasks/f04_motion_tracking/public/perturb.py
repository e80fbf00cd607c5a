"""Domain randomisation and hidden-evaluation perturbations of the G1 (one ``Perturbation`` per episode).

Model-side: link masses (inertia scaled with them) and centre-of-mass offsets, joint Coulomb friction,
PD gain scales, foot friction, floor roughness. Signal-side: encoder bias and Gaussian sensor noise on the observation,
one or two policy steps of action latency, and pushes (an instantaneous change of the pelvis velocity).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import mujoco
import numpy as np

from .g1_constants import G1

__all__ = ["NOMINAL", "Perturbation", "Push", "sample_perturbation"]


@dataclass(frozen=True)
class Push:
    """Pelvis velocity change ``dv`` [m/s] (world x, y) at ``time`` [s]."""

    time: float
    dv: tuple[float, float]


@dataclass(frozen=True)
class Perturbation:
    """One episode's perturbation (defaults: the nominal robot)."""

    mass_scale: tuple[float, ...] = ()
    """Per body (``model.nbody``) mass factor [1]; empty: 1."""
    com_offset: tuple[tuple[float, float, float], ...] = ()
    """Per body COM shift [m]; empty: 0."""
    joint_friction: tuple[float, ...] = ()
    """Per joint frictionloss [N m]; empty: 0."""
    kp_scale: tuple[float, ...] = ()
    kd_scale: tuple[float, ...] = ()
    foot_friction: float | None = None
    encoder_bias: tuple[float, ...] = ()
    """Per joint offset added to the measured angle [rad]."""
    noise_std: dict = field(default_factory=dict)
    """Std of Gaussian noise per observed signal: ``joint_pos`` [rad], ``joint_vel`` [rad/s],
    ``lin_vel`` [m/s], ``ang_vel`` [rad/s]."""
    latency: int = 0
    """Policy steps between an action's computation and its application [1]."""
    pushes: tuple[Push, ...] = ()
    terrain: float = 0.0
    """Peak-to-peak height of the floor's roughness [m] (models built with ``terrain=True``)."""
    terrain_seed: int = 0

    def apply(self, model: mujoco.MjModel) -> None:
        """Edit a compiled model in place (call on a fresh copy)."""
        if self.mass_scale:
            s = np.asarray(self.mass_scale)
            model.body_mass[:] *= s
            model.body_inertia[:] *= s[:, None]
        if self.com_offset:
            model.body_ipos[:] += np.asarray(self.com_offset)
        jdofs = [model.jnt_dofadr[model.joint(j).id] for j in G1.joints]
        if self.joint_friction:
            model.dof_frictionloss[jdofs] = self.joint_friction
        if self.kp_scale:
            kp = np.asarray(G1.kp) * np.asarray(self.kp_scale)
            model.actuator_gainprm[:, 0] = kp
            model.actuator_biasprm[:, 1] = -kp
        if self.kd_scale:
            model.actuator_biasprm[:, 2] = -np.asarray(G1.kd) * np.asarray(self.kd_scale)
        if model.nhfield:
            _roughen(model, self.terrain, self.terrain_seed)
        if self.foot_friction is not None:
            for g in range(model.ngeom):
                if "foot" in (model.geom(g).name or ""):
                    model.geom_friction[g, 0] = self.foot_friction


NOMINAL = Perturbation()
TERRAIN_WAVELENGTH = 0.4
"""Correlation length of the floor roughness [m] (random values on a 0.4 m grid, bilinearly refined)."""


def _roughen(model: mujoco.MjModel, height: float, seed: int) -> None:
    """Fill the ``terrain`` height field: heights in [-height/2, height/2] [m], flat when ``height`` is 0."""
    nrow, ncol = int(model.hfield_nrow[0]), int(model.hfield_ncol[0])
    geom = model.geom("floor").id
    if height <= 0:
        model.hfield_data[:] = 0.0
        model.hfield_size[0, 2] = 0.01
        model.geom_pos[geom, 2] = 0.0
        return
    sx, sy = 2 * model.hfield_size[0, 0], 2 * model.hfield_size[0, 1]
    cx, cy = int(np.ceil(sx / TERRAIN_WAVELENGTH)) + 1, int(np.ceil(sy / TERRAIN_WAVELENGTH)) + 1
    coarse = np.random.default_rng(seed).uniform(0.0, 1.0, (cy, cx))
    r, c = np.linspace(0, cy - 1, nrow), np.linspace(0, cx - 1, ncol)
    r0, c0 = np.minimum(r.astype(int), cy - 2), np.minimum(c.astype(int), cx - 2)
    fr, fc = (r - r0)[:, None], (c - c0)[None, :]
    fine = (
        coarse[r0][:, c0] * (1 - fr) * (1 - fc)
        + coarse[r0 + 1][:, c0] * fr * (1 - fc)
        + coarse[r0][:, c0 + 1] * (1 - fr) * fc
        + coarse[r0 + 1][:, c0 + 1] * fr * fc
    )
    model.hfield_data[:] = fine.reshape(-1)
    model.hfield_size[0, 2] = height
    model.geom_pos[geom, 2] = -height / 2


def sample_perturbation(
    rng: np.random.Generator, model: mujoco.MjModel, strength: float = 1.0
) -> Perturbation:
    """A random perturbation (``strength`` 1: the hidden-evaluation ranges; 0: nominal).

    Ranges at strength 1: masses x U(0.9, 1.1), COM offsets U(-2.5, 2.5) cm on pelvis and torso,
    joint friction U(0, 0.3) N m, kp and kd x U(0.85, 1.15), foot friction U(0.3, 1.2), encoder
    bias U(-0.01, 0.01) rad, noise std 0.01 rad, 0.1 rad/s, 0.05 m/s, 0.05 rad/s, latency 1 or 2
    steps, one push of U(0.2, 0.5) m/s in a random direction every U(4, 6) s, floor roughness of
    U(0, 2) cm peak to peak (on models built with ``terrain=True``).
    """
    nb, n = model.nbody, G1.dof
    a = float(strength)
    com = np.zeros((nb, 3))
    for body in ("pelvis", "torso_link"):
        com[model.body(body).id] = rng.uniform(-0.025, 0.025, 3) * a
    pushes, t = [], rng.uniform(4.0, 6.0)
    while t < 19.0 and a > 0:
        ang, mag = rng.uniform(0, 2 * np.pi), rng.uniform(0.2, 0.5) * a
        pushes.append(Push(float(t), (float(mag * np.cos(ang)), float(mag * np.sin(ang)))))
        t += rng.uniform(4.0, 6.0)
    return Perturbation(
        mass_scale=tuple(1.0 + a * rng.uniform(-0.1, 0.1, nb)),
        com_offset=tuple(map(tuple, com)),
        joint_friction=tuple(a * rng.uniform(0.0, 0.3, n)),
        kp_scale=tuple(1.0 + a * rng.uniform(-0.15, 0.15, n)),
        kd_scale=tuple(1.0 + a * rng.uniform(-0.15, 0.15, n)),
        foot_friction=float(0.75 + a * rng.uniform(-0.45, 0.45)),
        encoder_bias=tuple(a * rng.uniform(-0.01, 0.01, n)),
        noise_std={"joint_pos": 0.01 * a, "joint_vel": 0.1 * a, "lin_vel": 0.05 * a, "ang_vel": 0.05 * a},
        latency=int(rng.integers(1, 3)) if a > 0 else 0,
        pushes=tuple(pushes),
        terrain=float(a * rng.uniform(0.0, 0.02)),
        terrain_seed=int(rng.integers(2**31)),
    )
