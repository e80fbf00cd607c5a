"""Running a submitted ``trim.py`` in the sandbox: the feedforward/probe/adapt protocol.

Protocol (all calls run in ``rle_design.sandbox.Sandbox``, in a copy of the robot's directory):

* ``plan_probe() -> (15, n)`` poses [rad], chosen once as one batch; the verifier measures the home
  pose (``helpers.HOME``) first and then these 15 (clipped into the joint ranges);
* ``adapt(probes) -> params`` where ``probes = {"arm": "submitted" | "reference", "q": (16, n),
  "tau": (16, n)}``: measured holding torques [N m] of one device copy (row 0 = home);
* ``feedforward(q, params) -> (n,)`` servo torque [N m] at pose q; ``params=None`` asks for the
  nominal feedforward of the submitted leader, otherwise ``params`` is exactly what ``adapt`` returned.

The protocol is declared in ``TRIM`` and served by ``rle_tasks.core.runtime.policy.PolicyRunner`` with one
child per robot (no restarts, no fault limit): a fault that ends the child (a hang) answers every
later call with ``sandbox.dead``. Every fault is recorded, never raised.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rle_design.sandbox import ParticipantFault, SandboxLimits
from rle_tasks.core.runtime.policy import PolicyRunner
from rle_tasks.core.runtime.protocol import Budget, FunctionSpec, Protocol

N_PLANNED = 15
PLAN_TIMEOUT_S = 5.0
ADAPT_TIMEOUT_S = 5.0
FF_TIMEOUT_S = 2.0
LIMITS = SandboxLimits(cpu_seconds=60.0, call_timeout_s=PLAN_TIMEOUT_S, startup_timeout_s=20.0)
BUDGET = Budget(max_faults=None, cpu_s=60.0, restart=False)
TRIM = Protocol(
    module="trim",
    functions=(
        FunctionSpec("plan_probe", "()", returns=(N_PLANNED, "n"), timeout_s=PLAN_TIMEOUT_S),
        FunctionSpec(
            "adapt",
            "probes: {'arm': 'submitted' | 'reference', 'q': (16, n) [rad], 'tau': (16, n) [N m]}",
            returns=None,
            timeout_s=ADAPT_TIMEOUT_S,
        ),
        FunctionSpec(
            "feedforward",
            "q: (n,) [rad], params: what adapt returned, or None",
            returns=("n",),
            timeout_s=FF_TIMEOUT_S,
        ),
    ),
)


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
        self.runner = PolicyRunner(
            path, TRIM, dims={"n": dof}, hang_cap_s=hang_cap_s, budget=BUDGET, limits=LIMITS
        )

    def __enter__(self) -> TrimRunner:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        self.runner.close()

    @property
    def faults(self) -> list[ParticipantFault]:
        """Every fault so far, in call order."""
        return [r.fault for r in self.runner.faults]

    def plan(self, ranges: np.ndarray) -> np.ndarray | None:
        """The 15 planned probe poses, clipped into ``ranges``; None on a fault."""
        out = self.runner.try_call("plan_probe")
        if out is None:
            return None
        return np.clip(np.asarray(out, float), ranges[:, 0], ranges[:, 1])

    def adapt(self, arm: str, q: np.ndarray, tau: np.ndarray):
        """Adapted parameters (opaque), or None on a fault."""
        probes = {"arm": arm, "q": np.asarray(q, float), "tau": np.asarray(tau, float)}
        return self.runner.try_call("adapt", probes)

    def feedforward(self, q: np.ndarray, params) -> np.ndarray | None:
        """Feedforward torque at q [N m], or None on a fault."""
        out = self.runner.try_call("feedforward", np.asarray(q, float), params)
        return None if out is None else np.asarray(out, float)

    @property
    def alive(self) -> bool:
        return self.runner.alive
