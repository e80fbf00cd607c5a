"""Rebuild the final state of a metered session by replaying its ledger on the same environment.

A sealed ledger records every charged operation: resets and each executed action's float64 bytes
(``rle_design.ledger.records``). MuJoCo is deterministic for the same model, build and inputs, so
replaying the records on a fresh ``MjData`` of the same environment definition reproduces the
session's final state exactly; the simulation time recorded after each record is checked on the
way, so a replay that diverges (another scene, another MuJoCo) is refused rather than scored.
Verify the ledger first (``rle_design.ledger.verify_ledger``): replay trusts its integrity.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

import mujoco
import numpy as np

from rle_design.errors import RleError
from rle_design.rollout.env import EnvDefinition

__all__ = ["ReplayError", "check_range", "replay"]


class ReplayError(RleError):
    """A ledger cannot be replayed on the environment (other scene, malformed action, divergence)."""

    code = "replay.error"


def check_range(action: np.ndarray, low: np.ndarray, high: np.ndarray, seq: object) -> None:
    """Refuse a recorded action outside the environment's range: the server records actions as
    applied (clipped), so only an altered or foreign ledger holds one (``ledger.action_out_of_range``)."""
    outside = np.flatnonzero((action < low) | (action > high))
    if outside.size:
        i = int(outside[0])
        raise ReplayError(
            f"seq {seq}: action entry {i} is {action[i]!r}, outside the range [{low[i]}, {high[i]}] the server "
            f"applies ({outside.size} entries outside)",
            code="ledger.action_out_of_range",
        )


def replay(
    env: EnvDefinition,
    ledger_path: str | Path,
    model: mujoco.MjModel | None = None,
    on_step: Callable[[mujoco.MjModel, mujoco.MjData, str], None] | None = None,
) -> tuple[mujoco.MjModel, mujoco.MjData, int]:
    """Replay the session of ``ledger_path`` on ``env``.

    Args:
        env: The environment definition the session served.
        ledger_path: A verified, sealed ledger.
        model: ``env.build()`` when already compiled.
        on_step: Called with ``(model, data, kind)`` after every replayed reset (``kind="reset"``) and
            every executed action (``"steps"``), e.g. to evaluate a task's stages along the session.

    Returns:
        (model, data at the end of the session, executed actions replayed).

    Raises:
        ReplayError: ``replay.other_scene`` (the ledger names another model digest),
            ``replay.bad_action`` (an action of the wrong length), ``ledger.action_out_of_range``
            (an action the server would have clipped), ``replay.diverged`` (simulation
            time differs from the recorded one), ``replay.malformed``.
    """
    model = env.build() if model is None else model
    env.prepare(model)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    size = env.action_size(model)
    low, high = env.action_range(model)
    n_actions = 0
    try:
        lines = Path(ledger_path).read_text().splitlines()
        records = [json.loads(line) for line in lines]
    except (OSError, ValueError) as exc:
        raise ReplayError(f"ledger cannot be read for replay: {exc}", code="replay.malformed") from None
    if not records or records[0].get("kind") != "open":
        raise ReplayError("ledger has no open record", code="replay.malformed")
    recorded = records[0]["payload"].get("model_sha256")
    if recorded != env.fingerprint():
        raise ReplayError(
            f"ledger was recorded on scene {str(recorded)[:12]}..., this environment is "
            f"{env.fingerprint()[:12]}...",
            code="replay.other_scene",
        )
    for rec in records[1:]:
        kind, payload = rec.get("kind"), rec.get("payload", {})
        if kind == "reset":
            env.reset(model, data)
            if on_step is not None:
                on_step(model, data, "reset")
        elif kind == "steps":
            for h in payload.get("actions", []):
                try:
                    action = np.frombuffer(bytes.fromhex(h), dtype=np.float64)
                except (TypeError, ValueError):
                    raise ReplayError(
                        f"seq {rec.get('seq')}: action is not hex", code="replay.bad_action"
                    ) from None
                if action.shape != (size,):
                    raise ReplayError(
                        f"seq {rec.get('seq')}: action has {action.size} numbers, the environment takes {size}",
                        code="replay.bad_action",
                    )
                check_range(action, low, high, rec.get("seq"))
                env.step(model, data, action.copy())
                n_actions += 1
                if on_step is not None:
                    on_step(model, data, "steps")
        else:
            continue
        if abs(float(payload.get("time", data.time)) - data.time) > 1e-9:
            raise ReplayError(
                f"seq {rec.get('seq')}: replay time {data.time:.6f} s differs from the recorded "
                f"{payload.get('time')} s",
                code="replay.diverged",
            )
    return model, data, n_actions
