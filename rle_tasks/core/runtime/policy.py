"""Running submitted code under a declared protocol: hang caps, compute and fault budgets, restarts.

A family declares what a submission must expose as a ``Protocol`` of ``FunctionSpec`` entries (name,
arguments, return shape with symbolic dimensions such as ``("nu",)``, finiteness, per-call timeout;
``protocol``) and runs the submitted file with a ``PolicyRunner``:

* every call runs in ``rle_design.sandbox.Sandbox`` with a timeout of
  ``min(declared timeout, hang_cap_s)`` (``VerifyContext.hang_cap_s``);
* the CPU time of all children of one runner is bounded by ``Budget.cpu_s`` (each new child gets the
  remainder as its ``RLIMIT_CPU``, rounded up to whole seconds; once it is spent, calls fault with
  ``policy.cpu_budget`` without starting a child);
* with ``Budget.restart`` a fault closes the child and the next call starts a fresh one; a hang
  (``sandbox.timeout``, ``sandbox.cpu``) is not retried: it ends the runner at once. Without restarts
  one child serves the whole run and a fault that ended it answers every later call (``sandbox.dead``);
* after ``Budget.max_faults`` faults (or a hang) later calls fault with ``policy.fault_budget``
  without starting a child.

Every fault, refusals included, is kept as a ``FaultRecord`` for the report. ``call`` raises the
``ParticipantFault``; ``try_call`` returns None instead.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from rle_design.errors import RleError
from rle_design.sandbox import ParticipantFault, Sandbox, SandboxLimits
from rle_tasks.core.runtime.protocol import Budget, Protocol

POLICY_FAULT_CODES: dict[str, str] = {
    "policy.fault_budget": "the fault budget is used up (or a hang ended the run); the function was not called",
    "policy.cpu_budget": "the cumulative CPU-time budget is used up; the function was not called",
    "onnx.size": "the ONNX file is larger than the size cap",
    "onnx.path": "the ONNX file is missing, not a regular file, or outside the submission directory",
    "onnx.external_data": "the ONNX model references external data files",
    "onnx.load": "the ONNX file cannot be parsed or loaded by onnxruntime",
    "onnx.signature": "the ONNX model's input or output names differ from the declared ones",
    "onnx.shape": "an ONNX input or output has the wrong shape",
    "onnx.run": "onnxruntime failed while running the model",
    "onnx.timeout": "one inference ran past its wall-clock cap",
    "onnx.nonfinite": "an ONNX output holds NaN or infinity",
}
HANG_CODES = ("sandbox.timeout", "sandbox.cpu")
"""Fault codes of a hang: never retried."""


class PolicyFault(ParticipantFault):
    """A participant fault raised by the policy layer (budgets, ONNX), codes in ``POLICY_FAULT_CODES``.

    A ``ParticipantFault``, so verifiers that catch those handle it unchanged.
    """

    def __init__(self, code: str, message: str, detail: str = "", *, path: str | None = None) -> None:
        if code not in POLICY_FAULT_CODES:
            raise ValueError(
                f"unknown policy fault code '{code}'. Known codes: {', '.join(POLICY_FAULT_CODES)}"
            )
        RleError.__init__(self, message, code=code, path=path)
        self.detail = detail

    def __reduce__(self):
        return (_rebuild_policy_fault, (self.code, self.message, self.detail, self.path))


def _rebuild_policy_fault(code: str, message: str, detail: str, path: str | None) -> PolicyFault:
    return PolicyFault(code, message, detail, path=path)


@dataclass(frozen=True)
class FaultRecord:
    """One fault of one call, as kept for the report.

    Attributes:
        function: The called function.
        fault: The fault (its ``code``, ``message`` and ``detail``).
    """

    function: str
    fault: ParticipantFault

    @property
    def code(self) -> str:
        return self.fault.code

    @property
    def message(self) -> str:
        return self.fault.message


def distinct(records: tuple[FaultRecord, ...] | list[FaultRecord]) -> list[FaultRecord]:
    """``records`` without repeats of the same (code, message), in order of first occurrence."""
    seen: set[tuple[str, str]] = set()
    out = []
    for r in records:
        if (r.code, r.message) not in seen:
            seen.add((r.code, r.message))
            out.append(r)
    return out


class PolicyRunner:
    """One submitted file served under a ``Protocol`` (see the module docstring for the rules).

    Use as a context manager; not thread-safe. ``call`` has the signature of ``Sandbox.call``, so a
    runner can stand in for a sandbox.

    Args:
        path: The submitted ``.py`` file; its directory is copied into each child's working directory.
        protocol: The declared functions.
        dims: Values of the symbolic dimensions of the protocol's shapes.
        hang_cap_s: Upper bound of every per-call timeout [s] (``VerifyContext.hang_cap_s``).
        budget: Fault, CPU and restart rules.
        limits: Sandbox limits of each child; ``cpu_seconds`` is lowered to the unspent budget and
            ``call_timeout_s`` set to ``hang_cap_s``.
        workdir_files: Extra files copied into each child's working directory.

    Raises:
        MissingElement: ``policy.dims`` when a declared shape uses a symbol absent from ``dims``.
    """

    def __init__(
        self,
        path: Path | str,
        protocol: Protocol,
        *,
        dims: Mapping[str, int] = {},  # noqa: B006 - read only
        hang_cap_s: float = 30.0,
        budget: Budget = Budget(),  # noqa: B008 - frozen dataclass
        limits: SandboxLimits = SandboxLimits(),  # noqa: B008 - frozen dataclass
        workdir_files: Mapping[str, Path | str] = {},  # noqa: B006 - read only
    ) -> None:
        if not hang_cap_s > 0:
            raise ValueError(f"hang_cap_s must be > 0, got {hang_cap_s}")
        self.path = Path(path)
        self.protocol = protocol
        self.hang_cap_s = float(hang_cap_s)
        self.budget = budget
        self.limits = limits
        self._files = {k: Path(v) for k, v in workdir_files.items()}
        self._shapes = {f.name: f.shape(dims) for f in protocol.functions}
        self._faults: list[FaultRecord] = []
        self._n_faults = 0
        self._box: Sandbox | None = None
        self._starts = 0
        self._cpu_spent = 0.0
        self._ended: tuple[str, str] | None = None  # (code, reason) once calls are refused

    def __enter__(self) -> PolicyRunner:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # -- state ---------------------------------------------------------------------------------------
    @property
    def faults(self) -> tuple[FaultRecord, ...]:
        """Every fault so far, refusals included, in call order."""
        return tuple(self._faults)

    @property
    def n_faults(self) -> int:
        """Faults of the submitted code (refusals by the runner not counted)."""
        return self._n_faults

    @property
    def exhausted(self) -> bool:
        """True once further calls are refused (fault budget, hang or CPU budget)."""
        return self._ended is not None

    @property
    def restarts(self) -> int:
        """Children started after the first one."""
        return max(0, self._starts - 1)

    @property
    def cpu_used_s(self) -> float:
        """CPU time of all children so far, the live one included [s]."""
        return self._cpu_spent + (self._box.cpu_time_s if self._box is not None else 0.0)

    @property
    def alive(self) -> bool:
        """True while a child runs and can serve calls."""
        return self._box is not None and self._box.alive

    def close(self) -> None:
        """Close the live child (if any); idempotent. Later calls start a new one within the budgets."""
        box, self._box = self._box, None
        if box is not None:
            box.close()
            self._cpu_spent += box.cpu_time_s

    # -- calls ---------------------------------------------------------------------------------------
    def call(
        self,
        function: str,
        *args: Any,
        timeout: float | None = None,
        shape: tuple | None = None,
        finite: bool | None = None,
    ) -> Any:
        """Call a declared function in the child and return its checked result.

        Args:
            function: A function of the protocol.
            *args: Values of the sandbox wire format.
            timeout: Wall-clock cap [s]; default the declared one; always capped by ``hang_cap_s``.
            shape: Expected shape; default the declared (resolved) one.
            finite: Fault on NaN or infinity; default the declared setting.

        Raises:
            ParticipantFault: a fault of the submitted code, or a ``PolicyFault`` refusal.
            MissingElement: ``policy.undeclared`` for a function the protocol does not declare.
        """
        spec = self.protocol.function(function)
        where = f"{self.protocol.module}.{function}()"
        if self._ended is not None:
            code, reason = self._ended
            raise self._refuse(function, PolicyFault(code, f"{where}: not called: {reason}"))
        cap = min(spec.timeout_s if timeout is None else timeout, self.hang_cap_s)
        try:
            box = self._sandbox(where)
            return box.call(
                function,
                *args,
                timeout=cap,
                shape=self._shapes[function] if shape is None else shape,
                finite=spec.finite if finite is None else finite,
            )
        except PolicyFault as exc:
            raise self._refuse(function, exc) from None
        except ParticipantFault as exc:
            self._fault(function, exc)
            raise

    def wake(self) -> None:
        """``Sandbox.wake`` on the live child, if any: a call follows shortly (never raises, never
        counts as a call; a control loop passes it as ``run_episode(prepare=...)``)."""
        if self._box is not None and self._ended is None:
            self._box.wake()

    def try_call(self, function: str, *args: Any, **kw: Any) -> Any | None:
        """``call`` that returns None on a fault (the fault is recorded all the same)."""
        try:
            return self.call(function, *args, **kw)
        except ParticipantFault:
            return None

    def missing(self) -> list[str]:
        """Declared functions the module does not define (starts the child; faults propagate)."""
        box = self._sandbox(f"{self.protocol.module} (import)")
        return [name for name in self.protocol.names if not box.has(name)]

    # -- internals -----------------------------------------------------------------------------------
    def _sandbox(self, where: str) -> Sandbox:
        if self._box is not None:
            return self._box
        left = self.budget.cpu_s - self._cpu_spent
        if left <= 0:
            reason = f"the CPU budget of {self.budget.cpu_s:g} s is used up ({self._cpu_spent:.1f} s)"
            self._ended = ("policy.cpu_budget", reason)
            raise PolicyFault("policy.cpu_budget", f"{where}: not called: {reason}")
        limits = replace(
            self.limits,
            cpu_seconds=min(self.limits.cpu_seconds, math.ceil(left)),
            call_timeout_s=self.hang_cap_s,
        )
        self._box = Sandbox(self.path, limits=limits, workdir_files=self._files, name=self.protocol.module)
        self._starts += 1
        self._box.start()
        return self._box

    def _refuse(self, function: str, fault: PolicyFault) -> PolicyFault:
        self._faults.append(FaultRecord(function, fault))
        return fault

    def _fault(self, function: str, fault: ParticipantFault) -> None:
        self._faults.append(FaultRecord(function, fault))
        self._n_faults += 1
        if self.budget.restart:
            self.close()
            if fault.code in HANG_CODES:
                self._ended = (
                    "policy.fault_budget",
                    f"a hang ({fault.code}) ended the run; it is not retried",
                )
                return
        if self.budget.max_faults is not None and self._n_faults >= self.budget.max_faults:
            self._ended = (
                "policy.fault_budget",
                f"the fault budget of {self.budget.max_faults} faults is used up (last: {fault.code})",
            )
