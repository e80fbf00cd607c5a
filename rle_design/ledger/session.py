"""A metered MuJoCo session: resets and executed actions cost one step each, observations are free."""

from __future__ import annotations

import hashlib
import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from rle_design.errors import MissingElement
from rle_design.ledger.records import LedgerError, LedgerWriter
from rle_design.rollout.env import EnvDefinition
from rle_design.scene.elements import element_id

ObserverFn = Callable[[mujoco.MjModel, mujoco.MjData], Any]


@dataclass(frozen=True)
class MeteredEnv(EnvDefinition):
    """A generic environment from one MJCF string, ``n_substeps`` physics steps per action.

    Attributes:
        xml: MJCF of the scene (a string, compiled in the server process).
        n_substeps: Physics steps per executed action; the control period is
            ``n_substeps * model.opt.timestep`` [s].
        observers: Extra observations computed server-side, ``((name, fn(model, data)), ...)``; the
            functions must be importable module-level callables (they cross to the server process)
            and return wire-format values (numbers, strings, lists, dicts, ndarrays).
        keyframe: Name of the keyframe a reset restores; None resets to the model's default state.
    """

    xml: str
    n_substeps: int = 10
    observers: tuple[tuple[str, ObserverFn], ...] = ()
    keyframe: str | None = None

    def __post_init__(self) -> None:
        if self.n_substeps < 1:
            raise ValueError(f"MeteredEnv.n_substeps must be >= 1, got {self.n_substeps}")
        reserved = {"qpos", "qvel", "time"} & {name for name, _ in self.observers}
        if reserved:
            raise ValueError(f"observer names {sorted(reserved)} clash with qpos/qvel/time")

    def build(self) -> mujoco.MjModel:
        try:
            return mujoco.MjModel.from_xml_string(self.xml)
        except ValueError as exc:
            raise LedgerError(f"environment model does not compile: {exc}", code="ledger.bad_model") from None

    def fingerprint(self) -> str:
        return hashlib.sha256(self.xml.encode()).hexdigest()

    def prepare(self, model: mujoco.MjModel) -> None:
        self._key_id(model)

    def _key_id(self, model: mujoco.MjModel) -> int:
        if self.keyframe is None:
            return -1
        try:
            return element_id(model, "keyframe", self.keyframe)
        except MissingElement as exc:
            raise LedgerError(exc.message, code="ledger.bad_model") from None

    def reset(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        key = self._key_id(model)
        if key >= 0:
            mujoco.mj_resetDataKeyframe(model, data, key)
        else:
            mujoco.mj_resetData(model, data)
        mujoco.mj_forward(model, data)

    def observe(self, model: mujoco.MjModel, data: mujoco.MjData) -> dict[str, Any]:
        obs = super().observe(model, data)
        for name, fn in self.observers:
            obs[name] = fn(model, data)
        return obs


class MeteredSession:
    """Server-side session: owns the model, the budget and (when metered) the ledger writer.

    Args:
        env: The environment.
        task_id: Task the ledger belongs to.
        budget: Charged steps allowed, or None for unlimited.
        key: Ledger HMAC key; None runs unmetered (no ledger; used to measure the overhead).
        ledger_path: New ledger file (required with ``key``).
        actions_per_record: Consecutive executed actions grouped in one ``steps`` record (group
            commit; 1 writes one record per action). Resets and the seal close the group.
        wall_time_s: Wall-clock time the session may charge steps for, counted from its start [s];
            None for unlimited. The open record states it and the seal records the time used, so a
            verifier can require a time-limited session.
        model: ``env.build()`` when the caller compiled it already (``env.prepare`` done).
        meta: Extra fields of the open record.
        attempt: The attempt the session belongs to (issued by the operator, recorded in the open
            record; a verifier told the attempt refuses a ledger of another).

    An action outside the environment's range (``action_range``) is clipped, as the environment
    would; the ledger stores the applied action and the reply says how many entries were clipped
    (``clipped``; ``info()["actions_clipped"]`` counts the actions clipped so far).
    """

    def __init__(
        self,
        env: MeteredEnv,
        *,
        task_id: str,
        budget: int | None,
        key: bytes | None = None,
        ledger_path: Path | None = None,
        actions_per_record: int = 16,
        wall_time_s: float | None = None,
        model: mujoco.MjModel | None = None,
        meta: dict[str, Any] | None = None,
        attempt: str = "",
    ) -> None:
        if actions_per_record < 1:
            raise ValueError(f"actions_per_record must be >= 1, got {actions_per_record}")
        if wall_time_s is not None and not (math.isfinite(wall_time_s) and wall_time_s > 0):
            raise ValueError(f"wall_time_s must be positive and finite, got {wall_time_s}")
        self._t0 = time.monotonic()
        self.wall_time_s = wall_time_s
        if model is None:
            model = env.build()
            env.prepare(model)
        self.model = model
        self.data = mujoco.MjData(self.model)
        self.env = env
        self.task_id = task_id
        self.budget = budget
        self.steps_used = 0
        self.writer: LedgerWriter | None = None
        if key is not None:
            if ledger_path is None:
                raise LedgerError("a metered session needs a ledger path", code="ledger.no_path")
            meta = {
                **(meta or {}),
                "attempt": str(attempt),
                "budget": budget,
                "model_sha256": env.fingerprint(),
                "n_substeps": env.n_substeps,
                "timestep": float(self.model.opt.timestep),
            }
            if wall_time_s is not None:
                meta["wall_time_s"] = float(wall_time_s)
            self.writer = LedgerWriter(ledger_path, key, task_id, meta)
        self.attempt = str(attempt)
        self._set_action_range()
        self.actions_per_record = actions_per_record
        self._group: list[str] = []
        self._group_end: tuple[int, float, float] = (0, 0.0, 0.0)
        self._wall = 0.0
        self.actions_clipped = 0
        self.last_clipped = 0
        mujoco.mj_forward(self.model, self.data)

    def _set_action_range(self) -> None:
        self._ctrl = np.empty(self.env.action_size(self.model))
        self._low, self._high = (np.asarray(b, dtype=np.float64) for b in self.env.action_range(self.model))

    @property
    def elapsed_s(self) -> float:
        """Wall-clock time since the session started [s]."""
        return time.monotonic() - self._t0

    @property
    def sealed(self) -> bool:
        return self.writer is not None and self.writer.sealed

    def _charge(self) -> None:
        if self.sealed:
            raise LedgerError("the session is sealed; no more resets or steps", code="ledger.sealed")
        if self.wall_time_s is not None and self.elapsed_s > self.wall_time_s:
            raise LedgerError(
                f"the session's {self.wall_time_s:.0f} s are over ({self.elapsed_s:.0f} s since it started); "
                "observations and the seal still work",
                code="ledger.time_exhausted",
            )
        if self.budget is not None and self.steps_used >= self.budget:
            raise LedgerError(
                f"{self.steps_used} of {self.budget} steps used; resets and executed actions cost one step each, "
                "observations are free",
                code="ledger.budget_exhausted",
            )
        self.steps_used += 1
        self._stamp()

    def _stamp(self) -> None:
        """The wall clock of the step being charged, floored to the millisecond [s]."""
        self._wall = math.floor(self.elapsed_s * 1000.0) / 1000.0

    def reset(self, options: dict[str, Any] | None = None) -> dict[str, Any]:
        """Reset the simulation (one charged step); returns the observation.

        Raises:
            LedgerError: ``ledger.bad_request`` for options (a single-scene session takes none).
        """
        if options:
            raise LedgerError(
                f"reset takes no options in this session, got {sorted(options)}", code="ledger.bad_request"
            )
        self.commit()
        self._charge()
        self.env.reset(self.model, self.data)
        if self.writer is not None:
            self.writer.append(
                "reset", {"steps": self.steps_used, "time": self.data.time, "wall": self._wall}
            )
        return self.observe()

    def step(self, action: Any, *, defer_record: bool = False) -> dict[str, Any]:
        """Apply ``action`` as ``ctrl`` for ``n_substeps`` physics steps (one charged step).

        The action joins the open group of the ledger, written as one ``steps`` record once it holds
        ``actions_per_record`` actions. With ``defer_record`` even a full group waits for
        ``commit(force=False)``: the server replies first and records while the agent reads the
        reply. The step is charged either way.

        Raises:
            LedgerError: ``ledger.bad_action`` (wrong shape or non-finite; not charged),
                ``ledger.budget_exhausted``, ``ledger.sealed``.
        """
        try:
            arr = np.asarray(action, dtype=np.float64)
        except (TypeError, ValueError):
            arr = None
        if arr is None or arr.shape != self._ctrl.shape:
            got = "non-numeric" if arr is None else f"shape {arr.shape}"
            what = "the actuators' ctrl" if self._ctrl.size == self.model.nu else "the environment's action"
            raise LedgerError(
                f"action must be {self._ctrl.size} real numbers ({what}), got {got}",
                code="ledger.bad_action",
            )
        self._ctrl[:] = arr
        if not np.isfinite(self._ctrl).all():
            raise LedgerError("action holds NaN or infinity", code="ledger.bad_action")
        outside = (self._ctrl < self._low) | (self._ctrl > self._high)
        self.last_clipped = int(outside.sum())
        self._charge()
        if self.last_clipped:
            np.clip(self._ctrl, self._low, self._high, out=self._ctrl)
            self.actions_clipped += 1
        self.env.step(self.model, self.data, self._ctrl)
        if self.writer is not None:
            self._group.append(self._ctrl.tobytes().hex())
            self._group_end = (self.steps_used, self.data.time, self._wall)
            if not defer_record and len(self._group) >= self.actions_per_record:
                self.commit()
        return self.observe()

    def commit(self, force: bool = True) -> None:
        """Write the open group of actions as one ``steps`` record; without ``force``, only once full."""
        if self._group and (force or len(self._group) >= self.actions_per_record):
            group, self._group = self._group, []
            self.writer.append_steps(group, *self._group_end)

    def observe(self) -> dict[str, Any]:
        """The environment's observation (free)."""
        return self.env.observe(self.model, self.data)

    def query(self, name: str, args: dict[str, Any]) -> Any:
        """A free, read-only question to the environment (``env.query``), e.g. a segmentation.

        Raises:
            LedgerError: ``ledger.bad_request`` when the environment has no such query.
        """
        fn = getattr(self.env, "query", None)
        if fn is None:
            raise LedgerError("this environment answers no queries", code="ledger.bad_request")
        return fn(self.model, self.data, name, args)

    def info(self) -> dict[str, Any]:
        """Budget and model dimensions (free)."""
        return {
            "task_id": self.task_id,
            "steps_used": self.steps_used,
            "budget": self.budget,
            "wall_time_s": self.wall_time_s,
            "elapsed_s": round(self.elapsed_s, 3),
            "sealed": self.sealed,
            "nq": self.model.nq,
            "nv": self.model.nv,
            "nu": self.model.nu,
            "action_size": int(self._ctrl.size),
            "action_low": [float(v) if np.isfinite(v) else None for v in self._low],
            "action_high": [float(v) if np.isfinite(v) else None for v in self._high],
            "actions_clipped": self.actions_clipped,
            "attempt": self.attempt,
            "n_substeps": self.env.n_substeps,
            "timestep": float(self.model.opt.timestep),
        }

    def seal(self) -> str:
        """Seal the ledger (idempotent); returns the seal hash, or "" when unmetered."""
        if self.writer is None:
            return ""
        if not self.writer.sealed:
            self.commit()
            extra = {} if self.wall_time_s is None else {"elapsed_s": round(self.elapsed_s, 3)}
            self._head = self.writer.seal(self.steps_used, extra)
        return self._head
