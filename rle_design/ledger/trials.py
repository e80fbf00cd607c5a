"""A verifier's replay of a ``SceneSet`` session's evaluation trials (``replay_trials``) and the development
steps a ledger charged before them (``development_steps``).

Each trial is rebuilt from the verifier's own scene set (its key and model digest must match the
reset record's), its recorded actions re-executed, and success decided by ``SceneSet.success`` after
every action; the seal's account of the trial is kept beside the replay's, for the verifier to compare.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from rle_design.ledger.scenes import EVALUATION, SceneSet
from rle_design.ledger.session import MeteredEnv

__all__ = ["TrialReplay", "development_steps", "replay_trials"]


@dataclass(frozen=True)
class TrialReplay:
    """One evaluation trial re-executed by the verifier.

    Attributes:
        trial: Trial index.
        scene: Scene key the ledger names.
        actions: Actions replayed.
        success_at: First action (1-based) after which ``SceneSet.success`` held, or None.
        recorded_success: What the seal says of the trial (None when the seal does not list it).
        model: The trial's model (for renders of its final state).
        data: The trial's final state.
    """

    trial: int
    scene: str
    actions: int
    success_at: int | None
    recorded_success: bool | None = None
    model: mujoco.MjModel | None = field(default=None, compare=False, repr=False)
    data: mujoco.MjData | None = field(default=None, compare=False, repr=False)

    @property
    def success(self) -> bool:
        return self.success_at is not None


def _records(path: Path) -> list[dict[str, Any]]:
    from rle_design.control.replay import ReplayError

    try:
        return [json.loads(line) for line in Path(path).read_text().splitlines()]
    except (OSError, ValueError) as exc:
        raise ReplayError(f"ledger cannot be read for replay: {exc}", code="replay.malformed") from None


def development_steps(path: Path) -> int:
    """Charged steps before the ledger's first evaluation reset (all of them without one)."""
    steps = 0
    for rec in _records(path):
        payload = rec.get("payload", {})
        if rec.get("kind") == "reset" and payload.get("phase") == EVALUATION:
            return steps
        if rec.get("kind") in ("reset", "steps"):
            steps = int(payload.get("steps", steps))
    return steps


def replay_trials(scenes: SceneSet, ledger_path: str | Path) -> list[TrialReplay]:
    """Re-execute every evaluation trial of a verified ledger on ``scenes`` (rebuilt by the verifier).

    Raises:
        ReplayError: ``replay.other_scene`` (a trial's scene is not the verifier's, by key or digest),
            ``replay.bad_action``, ``replay.diverged`` (simulation time differs), ``replay.malformed``.
    """
    from rle_design.control.replay import ReplayError

    recs = _records(Path(ledger_path))
    seal = recs[-1].get("payload", {}) if recs and recs[-1].get("kind") == "seal" else {}
    recorded = seal.get("trials") if isinstance(seal.get("trials"), list) else []
    out: list[TrialReplay] = []
    run: _Run | None = None
    for rec in recs:
        kind, payload = rec.get("kind"), rec.get("payload", {})
        if kind == "reset" and payload.get("phase") == EVALUATION:
            if run is not None:
                out.append(run.result(recorded))
            run = _Run.start(scenes, len(out), rec)
        elif kind == "steps" and run is not None:
            for h in payload.get("actions", []):
                run.step(h, rec.get("seq"))
        else:
            continue
        if abs(float(payload.get("time", run.data.time)) - run.data.time) > 1e-9:
            raise ReplayError(
                f"seq {rec.get('seq')}: replay time {run.data.time:.6f} s differs from the recorded {payload.get('time')} s",
                code="replay.diverged",
            )
    if run is not None:
        out.append(run.result(recorded))
    return out


class _Run:
    """One trial being replayed."""

    def __init__(
        self, scenes: SceneSet, trial: int, key: str, env: MeteredEnv, model: mujoco.MjModel
    ) -> None:
        self.scenes, self.trial, self.key, self.env, self.model = scenes, trial, key, env, model
        self.data = mujoco.MjData(model)
        env.reset(model, self.data)
        self.size = env.action_size(model)
        self.low, self.high = env.action_range(model)
        self.actions = 0
        self.success_at: int | None = None

    @classmethod
    def start(cls, scenes: SceneSet, trial: int, rec: dict[str, Any]) -> _Run:
        from rle_design.control.replay import ReplayError

        payload = rec.get("payload", {})
        if payload.get("trial") != trial:
            raise ReplayError(
                f"seq {rec.get('seq')}: evaluation reset of trial {payload.get('trial')}, expected {trial}",
                code="replay.malformed",
            )
        key = scenes.evaluation_key(trial)
        if payload.get("scene") != key:
            raise ReplayError(
                f"trial {trial} was played on scene '{payload.get('scene')}', expected '{key}'",
                code="replay.other_scene",
            )
        env = scenes.scene(key)
        model = env.build()
        env.prepare(model)
        if payload.get("scene_sha256") != env.fingerprint():
            raise ReplayError(
                f"trial {trial} was recorded on scene {str(payload.get('scene_sha256'))[:12]}..., the verifier's is "
                f"{env.fingerprint()[:12]}...",
                code="replay.other_scene",
            )
        return cls(scenes, trial, key, env, model)

    def step(self, action_hex: Any, seq: Any) -> None:
        from rle_design.control.replay import ReplayError, check_range

        try:
            action = np.frombuffer(bytes.fromhex(action_hex), dtype=np.float64)
        except (TypeError, ValueError):
            raise ReplayError(f"seq {seq}: action is not hex", code="replay.bad_action") from None
        if action.shape != (self.size,):
            raise ReplayError(
                f"seq {seq}: action has {action.size} numbers, the environment takes {self.size}",
                code="replay.bad_action",
            )
        check_range(action, self.low, self.high, seq)
        self.env.step(self.model, self.data, action.copy())
        self.actions += 1
        if self.success_at is None and self.scenes.success(self.env, self.model, self.data):
            self.success_at = self.actions

    def result(self, recorded: list[Any]) -> TrialReplay:
        rec = (
            recorded[self.trial]
            if self.trial < len(recorded) and isinstance(recorded[self.trial], dict)
            else {}
        )
        rs = rec.get("success")
        recorded_success = rs if isinstance(rs, bool) else None
        return TrialReplay(
            self.trial, self.key, self.actions, self.success_at, recorded_success, self.model, self.data
        )
