"""Environment definitions: one object says how a scene is built, reset, driven and watched.

The metered development environment (``rle_design.ledger.MeteredSession``, one charged step per
``step``) and the hidden evaluation (``EnvDefinition.episode`` with a submitted policy) both drive the
scene through the same ``apply_action`` and ``advance``, so what an agent develops against and what
the verifier measures cannot diverge. Subclasses override ``build`` and, where they need to,
``prepare``, ``reset``, ``observe`` and ``terms``.
"""

from __future__ import annotations

import hashlib
from collections.abc import Callable, Sequence
from typing import Any

import mujoco
import numpy as np

from rle_design.errors import RleError
from rle_design.excerpt import excerpt
from rle_design.rollout.episode import Episode, run_episode
from rle_design.rollout.terms import Term

__all__ = ["ActionError", "EnvDefinition", "PolicyFn", "advance"]

PolicyFn = Callable[[dict[str, Any]], Any]
"""Maps an observation to an action (one ctrl value per actuator)."""


class ActionError(RleError):
    """An action of the wrong shape, or not finite (a participant fault)."""

    code = "env.bad_action"


def advance(model: mujoco.MjModel, data: mujoco.MjData, ctrl: np.ndarray, nstep: int) -> None:
    """Hold ``ctrl`` for ``nstep`` physics steps, stepped in C."""
    data.ctrl[:] = ctrl
    mujoco.mj_step(model, data, nstep)


class EnvDefinition:
    """Base of environment definitions.

    Subclasses are frozen dataclasses (picklable: a definition crosses to the ledger server) with
    an ``n_substeps`` field: physics steps per action; the control period is
    ``n_substeps * timestep`` [s].
    """

    n_substeps: int = 10

    def build(self) -> mujoco.MjModel:
        """The compiled scene."""
        raise NotImplementedError(f"{type(self).__name__} must define build()")

    def fingerprint(self) -> str:
        """Digest identifying the scene (recorded in ledgers) [hex]."""
        return hashlib.sha256(repr(self).encode()).hexdigest()

    def prepare(self, model: mujoco.MjModel) -> None:
        """Checks once after ``build`` (names the definition relies on, ...)."""

    def reset(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """Initial state of an episode."""
        mujoco.mj_resetData(model, data)
        mujoco.mj_forward(model, data)

    observation_doc: str = "qpos, qvel, time"
    """The observation's keys in words, as the development workspace's ``client.py`` states them."""

    def observe(self, model: mujoco.MjModel, data: mujoco.MjData) -> dict[str, Any]:
        """What the controller sees: ``qpos``, ``qvel``, ``time`` (subclasses add more)."""
        return {"qpos": data.qpos.copy(), "qvel": data.qvel.copy(), "time": data.time}

    def terms(self, model: mujoco.MjModel) -> Sequence[Term]:
        """Fresh terms of one evaluation episode (termination, success, events)."""
        return ()

    def action_size(self, model: mujoco.MjModel) -> int:
        """Length of one action: the actuators' ctrl by default; an environment that maps a command
        layout onto its actuators (e.g. ``rle_design.control.TabletopEnv``) says its own."""
        return model.nu

    def action_range(self, model: mujoco.MjModel) -> tuple[np.ndarray, np.ndarray]:
        """(low, high) of each action entry: the actuators' ``ctrlrange`` where limited (MuJoCo clamps
        ctrl there), unbounded elsewhere; an environment with its own layout states its own."""
        size = self.action_size(model)
        low, high = np.full(size, -np.inf), np.full(size, np.inf)
        if size == model.nu:
            limited = model.actuator_ctrllimited.astype(bool)
            low[limited] = model.actuator_ctrlrange[limited, 0]
            high[limited] = model.actuator_ctrlrange[limited, 1]
        return low, high

    def action(self, model: mujoco.MjModel, action: Any) -> np.ndarray:
        """``action`` as a finite ctrl vector; raises ``ActionError`` naming what is wrong."""
        try:
            arr = np.asarray(action, dtype=np.float64)
        except (TypeError, ValueError):
            arr = None
        size = self.action_size(model)
        if arr is None or arr.shape != (size,):
            got = "non-numeric" if arr is None else f"shape {excerpt(arr.shape, 40)}"
            what = "the actuators' ctrl" if size == model.nu else "the environment's action"
            raise ActionError(f"action must be {size} real numbers ({what}), got {got}")
        if not np.isfinite(arr).all():
            raise ActionError("action holds NaN or infinity")
        return arr

    def step(self, model: mujoco.MjModel, data: mujoco.MjData, ctrl: np.ndarray) -> None:
        """Advance one control period with a checked ctrl vector."""
        advance(model, data, ctrl, self.n_substeps)

    def episode(
        self, model: mujoco.MjModel, data: mujoco.MjData, policy: PolicyFn, n_actions: int
    ) -> Episode:
        """Evaluation episode from the current state: ``policy(observe())`` every control period.

        The terms of ``terms(model)`` are evaluated every physics step they ask for; an invalid
        action raises ``ActionError`` (the caller records the participant fault).
        """

        def control(m: mujoco.MjModel, d: mujoco.MjData, t: float) -> None:
            d.ctrl[:] = self.action(m, policy(self.observe(m, d)))

        return run_episode(
            model,
            data,
            n_actions * self.n_substeps,
            control=control,
            control_every=self.n_substeps,
            terms=list(self.terms(model)),
        )
