"""Metered sessions over many scenes: a development phase, then a terminal evaluation phase of trials.

A ``SceneSet`` names the scenes one session may serve and picks one at every reset:

- **development**: ``reset(**options)`` loads ``scene_set.development_key(n, options)`` (n counts the
  development resets); each reset and executed action is one charged step of the budget;
- **evaluation** (when ``SceneSet.evaluation`` is set): ``reset(evaluation=True)`` starts the terminal
  phase; trial k plays ``scene_set.evaluation_key(k)``, and each further reset advances to the next
  trial. A trial takes at most ``EvaluationPhase.actions_per_trial`` actions, the phase at most
  ``EvaluationPhase.wall_time_s``; its resets and actions are recorded but do not count against the
  development budget. There is no way back to development.

Every reset record carries the scene's key, its model digest and the phase (and the trial), so a
verifier that can rebuild the scenes (``replay_trials``) re-executes each trial on its own scene and
decides success itself; the seal records the development steps and, per trial, the actions and
whether ``SceneSet.success`` held after some action (the session's own account, for the agent).
``trials`` replays them.
"""

from __future__ import annotations

import hashlib
import time
from collections import OrderedDict
from dataclasses import dataclass
from typing import Any

import mujoco

from rle_design.ledger.records import LedgerError
from rle_design.ledger.session import MeteredEnv, MeteredSession

__all__ = ["DEVELOPMENT", "EVALUATION", "EvaluationPhase", "SceneSession", "SceneSet"]

DEVELOPMENT = "development"
EVALUATION = "evaluation"


@dataclass(frozen=True)
class EvaluationPhase:
    """The terminal evaluation phase of a session.

    Attributes:
        trials: Number of trials.
        actions_per_trial: Executed actions one trial may take.
        wall_time_s: Wall time of the whole phase from its first reset [s]; None for unlimited.
    """

    trials: int
    actions_per_trial: int
    wall_time_s: float | None = None


class SceneSet:
    """Base of scene sets (subclasses are frozen, picklable dataclasses: a set crosses to the server).

    Subclasses define ``scene``, ``development_key`` and, with an evaluation phase,
    ``evaluation_key``; ``success`` says whether a scene's state counts as a trial's success.
    """

    n_substeps: int = 1
    evaluation: EvaluationPhase | None = None
    observation_doc: str = "qpos, qvel, time"
    cached_scenes: int = 4
    """Compiled scenes a session keeps (a reset to a cached scene does not recompile)."""

    def scene(self, key: str) -> MeteredEnv:
        """The environment of scene ``key``; raises ``LedgerError`` (``ledger.bad_scene``) for an unknown key."""
        raise NotImplementedError

    def development_key(self, index: int, options: dict[str, Any]) -> str:
        """Scene of development reset ``index`` (from 0) given the agent's reset options."""
        raise NotImplementedError

    def evaluation_key(self, trial: int) -> str:
        """Scene of evaluation trial ``trial`` (from 0)."""
        raise NotImplementedError

    def success(self, env: MeteredEnv, model: mujoco.MjModel, data: mujoco.MjData) -> bool:
        """Whether the state counts as success (False by default)."""
        return False

    def fingerprint(self) -> str:
        """Digest of the public description of the set (recorded in the open record) [hex]."""
        return hashlib.sha256(self.describe().encode()).hexdigest()

    def describe(self) -> str:
        """Public description (never secret-derived data)."""
        return type(self).__name__

    def session_doc(self) -> str:
        """How the session's resets work, for the workspace's ``client.py``."""
        return (
            "This session serves many scenes: each env.reset() starts the next development scene (charged). "
            + self.evaluation_doc()
        )

    def evaluation_doc(self) -> str:
        """The evaluation phase in words ("" without one)."""
        e = self.evaluation
        if e is None:
            return ""
        return (
            f"env.reset(evaluation=True) starts the terminal evaluation phase (no way back): trial 0 of "
            f"{e.trials} in unseen scenes, each further env.reset() the next trial; a trial takes at most "
            f"{e.actions_per_trial} actions, recorded but not charged to the development budget. "
            "env.info() shows the phase and the trials."
        )

    def action_size(self) -> int:
        """Numbers per action: the first development scene's (builds it); a subclass whose
        environments share one fixed action layout returns it without building a scene."""
        env = self.scene(self.development_key(0, {}))
        return env.action_size(env.build())

    def open_session(self, **kwargs: Any) -> SceneSession:
        """The server-side session (``rle_design.ledger.server`` calls this)."""
        return SceneSession(self, **kwargs)


@dataclass
class _Trial:
    scene: str
    actions: int = 0
    success_at: int | None = None

    def record(self) -> dict[str, Any]:
        return {
            "scene": self.scene,
            "actions": self.actions,
            "success": self.success_at is not None,
            "success_at": self.success_at,
        }


class SceneSession(MeteredSession):
    """Server-side session of a ``SceneSet`` (see the module docstring); ``budget`` limits development."""

    def __init__(self, scenes: SceneSet, **kwargs: Any) -> None:
        self.scenes = scenes
        self._cache: OrderedDict[str, tuple[MeteredEnv, mujoco.MjModel]] = OrderedDict()
        self.phase = DEVELOPMENT
        self.dev_resets = 0
        self.dev_steps = 0
        self.trials: list[_Trial] = []
        self._eval_t0: float | None = None
        key = scenes.development_key(0, {})
        env, model = self._load(key)
        self.key = key
        meta = {"scene_set": scenes.fingerprint(), "evaluation": _phase_meta(scenes.evaluation)}
        super().__init__(env, model=model, meta=meta, **kwargs)

    def _load(self, key: str) -> tuple[MeteredEnv, mujoco.MjModel]:
        if key in self._cache:
            self._cache.move_to_end(key)
            return self._cache[key]
        env = self.scenes.scene(key)
        model = env.build()
        env.prepare(model)
        self._cache[key] = (env, model)
        while len(self._cache) > max(1, self.scenes.cached_scenes):
            self._cache.popitem(last=False)
        return env, model

    def _charge(self) -> None:
        if self.phase == DEVELOPMENT:
            super()._charge()
            self.dev_steps += 1
            return
        if self.sealed:
            raise LedgerError("the session is sealed; no more resets or steps", code="ledger.sealed")
        phase = self.scenes.evaluation
        if self._eval_t0 is None:  # the phase's clock starts with the charge of its first reset
            self._eval_t0 = time.monotonic()
        if phase.wall_time_s is not None and time.monotonic() - self._eval_t0 > phase.wall_time_s:
            raise LedgerError(
                f"the evaluation phase's {phase.wall_time_s:.0f} s are over; the seal still works",
                code="ledger.time_exhausted",
            )
        self.steps_used += 1
        self._stamp()

    def _check_dev_budget(self) -> None:
        if self.budget is not None and self.dev_steps >= self.budget:
            raise LedgerError(
                f"{self.dev_steps} of {self.budget} development steps used; resets and executed actions cost one "
                "step each, observations are free. The evaluation phase (reset(evaluation=True)) is still open",
                code="ledger.budget_exhausted",
            )

    def reset(self, options: dict[str, Any] | None = None) -> dict[str, Any]:
        options = dict(options or {})
        start_eval = bool(options.pop("evaluation", False))
        self.commit()
        if self.sealed:
            raise LedgerError("the session is sealed; no more resets or steps", code="ledger.sealed")
        if start_eval:
            if self.scenes.evaluation is None:
                raise LedgerError("this session has no evaluation phase", code="ledger.bad_request")
            if self.phase == EVALUATION:
                raise LedgerError(
                    "the evaluation phase has started already; reset() advances to the next trial",
                    code="ledger.bad_request",
                )
            if options:
                raise LedgerError(
                    f"reset(evaluation=True) takes no other option, got {sorted(options)}",
                    code="ledger.bad_request",
                )
            self.phase = EVALUATION
        if self.phase == EVALUATION:
            if options:
                raise LedgerError(
                    f"evaluation resets take no options, got {sorted(options)}", code="ledger.bad_request"
                )
            k = len(self.trials)
            if k >= self.scenes.evaluation.trials:
                raise LedgerError(
                    f"all {k} evaluation trials are done; seal the session", code="ledger.trials_done"
                )
            key = self.scenes.evaluation_key(k)
        else:
            self._check_dev_budget()
            key = self.scenes.development_key(self.dev_resets, options)
        env, model = self._load(key)
        self._charge()
        if self.phase == EVALUATION:
            self.trials.append(_Trial(key))
        else:
            self.dev_resets += 1
        if model is not self.model:
            self.env, self.model, self.data = env, model, mujoco.MjData(model)
            self._set_action_range()
        self.key = key
        env.reset(self.model, self.data)
        if self.writer is not None:
            payload = {
                "steps": self.steps_used,
                "time": self.data.time,
                "wall": self._wall,
                "scene": key,
                "scene_sha256": env.fingerprint(),
                "phase": self.phase,
            }
            if self.phase == EVALUATION:
                payload["trial"] = len(self.trials) - 1
            self.writer.append("reset", payload)
        return self.observe()

    def step(self, action: Any, *, defer_record: bool = False) -> dict[str, Any]:
        if self.phase == EVALUATION:
            if not self.trials:
                raise LedgerError("no trial is running", code="ledger.bad_request")
            trial = self.trials[-1]
            if trial.actions >= self.scenes.evaluation.actions_per_trial:
                raise LedgerError(
                    f"trial {len(self.trials) - 1} has used its {trial.actions} actions; reset() starts the next trial",
                    code="ledger.trial_exhausted",
                )
        else:
            self._check_dev_budget()
        obs = super().step(action, defer_record=defer_record)
        if self.phase == EVALUATION:
            trial.actions += 1
            if trial.success_at is None and self.scenes.success(self.env, self.model, self.data):
                trial.success_at = trial.actions
        return obs

    def info(self) -> dict[str, Any]:
        info = super().info()
        phase = self.scenes.evaluation
        info.update(
            {
                "phase": self.phase,
                "scene": self.key,
                "development_steps": self.dev_steps,
                "trials": [t.record() for t in self.trials],
                "evaluation": _phase_meta(phase),
            }
        )
        return info

    def seal(self) -> str:
        if self.writer is None:
            return ""
        if not self.writer.sealed:
            self.commit()
            extra = {"development_steps": self.dev_steps, "trials": [t.record() for t in self.trials]}
            if self.wall_time_s is not None:
                extra["elapsed_s"] = round(self.elapsed_s, 3)
            self._head = self.writer.seal(self.steps_used, extra)
        return self._head


def _phase_meta(phase: EvaluationPhase | None) -> dict[str, Any] | None:
    if phase is None:
        return None
    return {
        "trials": phase.trials,
        "actions_per_trial": phase.actions_per_trial,
        "wall_time_s": phase.wall_time_s,
    }
