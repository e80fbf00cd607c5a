"""The shared ledger gate: every card limit re-checked on the records, even of a ledger signed with the key.

Forged ledgers are written with ``LedgerWriter`` and the verifier's own key: the stand-in for a leaked or
mishandled key (the MACs are right, so only the recount can catch them). Each limit has a ledger one
unit over it that must fail with its code, and the honest session of the same scene set must pass.
"""

import json
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

from rle_design.control.replay import ReplayError
from rle_design.ledger import (
    EvaluationPhase,
    LedgerClient,
    LedgerServer,
    Limits,
    check_ledger,
    replay_trials,
)
from rle_design.ledger.records import FORMAT
from rle_design.ledger.testing import forge_ledger

sys.path.insert(0, str(Path(__file__).parent))
from test_scene_sessions import KEY, Sliders  # noqa: E402

LIMITS = Limits(budget=5, wall_time_s=100.0, trials=2, actions_per_trial=3, evaluation_wall_time_s=10.0)
EVAL = {"trials": 2, "actions_per_trial": 3, "wall_time_s": 10.0}
H0 = np.zeros(1).tobytes().hex()


def _scenes() -> Sliders:
    return Sliders(evaluation=EvaluationPhase(trials=2, actions_per_trial=3, wall_time_s=10.0))


def forge(path: Path, records: list[tuple[str, dict]], seal: dict | None = None, **open_meta) -> Path:
    """A ledger signed with the verifier's key holding exactly ``records``, opened with the limits of
    ``LIMITS`` unless ``open_meta`` overrides them."""
    meta = {"attempt": "", "budget": 5, "wall_time_s": 100.0, "evaluation": EVAL, **open_meta}
    return forge_ledger(path, KEY, "t", meta, records, seal)


def dev(n: int, wall: float = 1.0) -> list[tuple[str, dict]]:
    return [("reset", {"wall": wall, "phase": "development", "scene": "dev/0"})] + [
        ("steps", {"actions": [H0] * (n - 1), "wall": wall})
    ] * (n > 1)


def trial(k: int, actions: int, wall: float = 2.0) -> list[tuple[str, dict]]:
    rec = [("reset", {"wall": wall, "phase": "evaluation", "trial": k, "scene": f"eval/{k}"})]
    return rec + [("steps", {"actions": [H0] * actions, "wall": wall})] * (actions > 0)


def sealed_trials(*actions: int) -> dict:
    return {
        "trials": [{"scene": f"eval/{k}", "actions": n, "success": False} for k, n in enumerate(actions)],
        "elapsed_s": 50.0,
    }


def test_an_honest_session_passes_with_its_counts(tmp_path):
    server = LedgerServer(_scenes(), key=KEY, ledger_path=tmp_path / "l.jsonl", socket_path=tmp_path / "s",
                          task_id="t", budget=5, wall_time_s=100.0, attempt="trial-7")  # fmt: skip
    with server, LedgerClient(server.socket_path) as c:
        c.reset()
        c.step([1.0])
        c.step([1.0])
        c.reset(evaluation=True)
        c.step([5.0])
        c.reset()
        c.seal()
    gate = check_ledger(tmp_path / "l.jsonl", KEY, "t", LIMITS, "trial-7")
    assert gate.ok, gate.message
    assert (gate.development_steps, gate.resets, gate.actions) == (3, 1, 3)
    assert [(t.scene, t.actions) for t in gate.trials] == [("eval/0", 1), ("eval/1", 0)]
    assert gate.attempt == "trial-7" and gate.attempt_bound
    opened = json.loads((tmp_path / "l.jsonl").read_text().splitlines()[0])["payload"]
    assert opened["format"] == FORMAT and opened["attempt"] == "trial-7"


def test_a_forged_ledger_within_every_limit_passes(tmp_path):
    path = forge(tmp_path / "l.jsonl", dev(5) + trial(0, 3) + trial(1, 3), sealed_trials(3, 3),
                 )  # fmt: skip
    gate = check_ledger(path, KEY, "t", LIMITS)
    assert gate.ok, gate.message
    assert gate.development_steps == 5 and not gate.attempt_bound


@pytest.mark.parametrize(
    "records, seal, meta, code",
    [
        # 6 development steps, budget 5 (the server refuses the 6th)
        (dev(6) + trial(0, 0), sealed_trials(0), {}, "ledger.over_budget"),
        # a trial of 4 actions, the card allows 3
        (dev(1) + trial(0, 4), sealed_trials(4), {}, "ledger.trial_too_long"),
        # three trials, the card has two
        (
            dev(1) + trial(0, 0) + trial(1, 0) + trial(2, 0),
            sealed_trials(0, 0, 0),
            {},
            "ledger.too_many_trials",
        ),
        # the seal says trial 0 took 1 action, the records hold 3
        (dev(1) + trial(0, 3), sealed_trials(1), {}, "ledger.seal_mismatch"),
        # a step charged at 150 s of a session limited to 100 s
        (dev(1, wall=150.0), {"elapsed_s": 160.0}, {}, "ledger.over_time"),
        # an evaluation step 11 s after the phase began (1 h in the card, 10 s here)
        (
            dev(1) + trial(0, 0, wall=2.0) + [("steps", {"actions": [H0], "wall": 13.0})],
            sealed_trials(1),
            {},
            "ledger.over_time",
        ),  # fmt: skip
        # wall stamps that run backwards
        (
            dev(2, wall=5.0)[:1] + [("steps", {"actions": [H0], "wall": 4.0})],
            {"elapsed_s": 9.0},
            {},
            "ledger.over_time",
        ),  # fmt: skip
        # the seal claims less wall time than the last charged step
        (dev(1, wall=80.0), {"elapsed_s": 20.0}, {}, "ledger.seal_mismatch"),
        # served with a larger budget than the card's
        (dev(1), {"elapsed_s": 1.0}, {"budget": 50}, "ledger.wrong_limits"),
        # served without the card's wall-time limit
        (dev(1), {"elapsed_s": 1.0}, {"wall_time_s": None}, "ledger.wrong_limits"),
        # served with a longer evaluation phase
        (
            dev(1),
            {"elapsed_s": 1.0},
            {"evaluation": {**EVAL, "actions_per_trial": 30}},
            "ledger.wrong_limits",
        ),
        # a ledger of the previous format (no attempt, no wall stamps)
        (dev(1), {"elapsed_s": 1.0}, {"format": 1}, "ledger.old_format"),
    ],
)
def test_each_limit_breach_is_refused_by_name(tmp_path, records, seal, meta, code):
    path = forge(tmp_path / "l.jsonl", records, seal, **meta)
    gate = check_ledger(path, KEY, "t", LIMITS)
    assert not gate.ok and gate.code == code, gate.message


def test_development_resets_are_limited_where_the_card_says(tmp_path):
    path = forge(tmp_path / "l.jsonl", dev(1) + dev(1) + dev(1), {"elapsed_s": 2.0})
    assert check_ledger(path, KEY, "t", Limits(budget=5, wall_time_s=100.0)).ok
    gate = check_ledger(path, KEY, "t", Limits(budget=5, wall_time_s=100.0, resets=2))
    assert gate.code == "ledger.too_many_resets"


def test_a_ledger_of_another_attempt_is_refused(tmp_path):
    path = forge(tmp_path / "l.jsonl", dev(1) + trial(0, 0), sealed_trials(0), attempt="A")
    assert check_ledger(path, KEY, "t", LIMITS, "A").ok
    gate = check_ledger(path, KEY, "t", LIMITS, "B")
    assert gate.code == "ledger.wrong_attempt" and "'A'" in gate.message and "'B'" in gate.message
    unbound = check_ledger(path, KEY, "t", LIMITS)
    assert unbound.ok and unbound.attempt == "A" and not unbound.attempt_bound


def test_authenticity_comes_first(tmp_path):
    path = forge(tmp_path / "l.jsonl", dev(1), {"elapsed_s": 1.0})
    assert check_ledger(path, b"x" * 32, "t", LIMITS).code == "ledger.forged_key"
    link = tmp_path / "link.jsonl"
    link.symlink_to(path)
    assert check_ledger(link, KEY, "t", LIMITS).code == "ledger.missing"


def test_the_server_clips_out_of_range_actions_and_says_so(tmp_path):
    """ctrlrange of the slider's motor is [-100, 100]: 500 is applied and recorded as 100."""
    server = LedgerServer(_scenes(), key=KEY, ledger_path=tmp_path / "l.jsonl", socket_path=tmp_path / "s",
                          task_id="t", budget=5, wall_time_s=100.0)  # fmt: skip
    with server, LedgerClient(server.socket_path) as c:
        c.reset()
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            c.step([500.0])
            c.step([50.0])
        assert len(caught) == 1 and "clipped" in str(caught[0].message)
        info = c.info()
        assert info["actions_clipped"] == 1 and info["action_high"] == [100.0]
        assert c.clipped_actions == 1
        c.seal()
    recs = [json.loads(line) for line in (tmp_path / "l.jsonl").read_text().splitlines()]
    actions = [a for r in recs if r["kind"] == "steps" for a in r["payload"]["actions"]]
    assert [np.frombuffer(bytes.fromhex(a))[0] for a in actions] == [100.0, 50.0]


def test_replay_refuses_a_recorded_action_the_server_would_have_clipped(tmp_path):
    big = np.array([500.0]).tobytes().hex()
    sha = _scenes().scene("eval/0").fingerprint()
    records = dev(1) + [
        ("reset", {"wall": 2.0, "phase": "evaluation", "trial": 0, "scene": "eval/0", "scene_sha256": sha}),
        ("steps", {"actions": [big], "wall": 2.0}),
    ]
    path = forge(tmp_path / "l.jsonl", records, sealed_trials(1))
    assert check_ledger(path, KEY, "t", LIMITS).ok  # within every count: only the replay knows the range
    with pytest.raises(ReplayError) as exc:
        replay_trials(_scenes(), path)
    assert exc.value.code == "ledger.action_out_of_range" and "500.0" in exc.value.message
