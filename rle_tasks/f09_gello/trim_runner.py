"""Running a submitted ``trim.py`` in the sandbox: the feedforward/probe/adapt protocol.

Protocol (all calls run in ``rle_design.sandbox.Sandbox``, in a copy of the robot's directory):

* ``plan_probe() -> (15, n)`` poses [rad], chosen once as one batch; the verifier measures the home
  pose (``helpers.HOME``) first and then these 15 (clipped into the joint ranges);
* ``adapt(probes) -> params`` where ``probes = {"arm": "submitted" | "reference", "q": (16, n),
  "tau": (16, n)}``: measured holding torques [N m] of one device copy (row 0 = home);
* ``feedforward(q, params) -> (n,)`` servo torque [N m] at pose q; ``params=None`` asks for the
  nominal feedforward of the submitted leader, otherwise ``params`` is exactly what ``adapt`` returned.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rle_design.sandbox import ParticipantFault, Sandbox, SandboxLimits

N_PLANNED = 15
PLAN_TIMEOUT_S = 5.0
ADAPT_TIMEOUT_S = 5.0
FF_TIMEOUT_S = 2.0
LIMITS = SandboxLimits(cpu_seconds=60.0, call_timeout_s=PLAN_TIMEOUT_S, startup_timeout_s=20.0)


class TrimRunner:
    """One robot's ``trim.py`` in a sandbox; every participant fault is recorded, never raised.

    Args:
        path: The submitted ``trim.py``.
        dof: Number of joints n.
        hang_cap_s: Upper bound of every per-call timeout [s] (``VerifyContext.hang_cap_s``).
    """

    def __init__(self, path: Path, dof: int, hang_cap_s: float = 30.0) -> None:
        self.path = path
        self.dof = dof
        self.hang_cap_s = hang_cap_s
        self.faults: list[ParticipantFault] = []
        self._box: Sandbox | None = None

    def __enter__(self) -> TrimRunner:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        if self._box is not None:
            self._box.close()
            self._box = None

    def _call(self, fn: str, *args, timeout: float, shape: tuple | None):
        timeout = min(timeout, self.hang_cap_s)
        try:
            if self._box is None:
                self._box = Sandbox(self.path, limits=LIMITS, name="trim")
                self._box.start()
            return self._box.call(fn, *args, timeout=timeout, shape=shape, finite=True)
        except ParticipantFault as exc:
            self.faults.append(exc)
            return None

    def plan(self, ranges: np.ndarray) -> np.ndarray | None:
        """The 15 planned probe poses, clipped into ``ranges``; None on a fault."""
        out = self._call("plan_probe", timeout=PLAN_TIMEOUT_S, shape=(N_PLANNED, self.dof))
        if out is None:
            return None
        return np.clip(np.asarray(out, float), ranges[:, 0], ranges[:, 1])

    def adapt(self, arm: str, q: np.ndarray, tau: np.ndarray):
        """Adapted parameters (opaque), or None on a fault."""
        probes = {"arm": arm, "q": np.asarray(q, float), "tau": np.asarray(tau, float)}
        return self._call("adapt", probes, timeout=ADAPT_TIMEOUT_S, shape=None)

    def feedforward(self, q: np.ndarray, params) -> np.ndarray | None:
        """Feedforward torque at q [N m], or None on a fault."""
        out = self._call("feedforward", np.asarray(q, float), params, timeout=FF_TIMEOUT_S, shape=(self.dof,))
        return None if out is None else np.asarray(out, float)

    @property
    def alive(self) -> bool:
        return self._box is not None and self._box.alive
