"""Replay of a family-05 recipe: the artifact contract, offline training in the sandbox, and the
mean-action baseline served over the protocol on a LIBERO-10 episode (a partial run)."""

import numpy as np
import pytest

from rle_tasks.envs.libero.replay import CKPT, SOLUTION_MAX_BYTES, check_solution, replay, train
from rle_tasks.f05_nanovla.task import HERE as F05

MEAN_ACTION = F05 / "solutions" / "baseline" / "mean_action.py"


@pytest.fixture
def demos(tmp_path):
    """Two stored episodes (only their actions matter to the recipes below)."""
    d = tmp_path / "demos"
    d.mkdir()
    for k, value in enumerate((0.1, 0.3)):
        a = np.full((5, 7), value, np.float32)
        np.savez(d / f"task00_init{k:02d}.npz", actions=a, state=np.zeros((6, 8)), language=np.array("x"))
    return d


def _solution(tmp_path, text: str | bytes):
    p = tmp_path / "solution.py"
    p.write_bytes(text if isinstance(text, bytes) else text.encode())
    return p


def test_the_artifact_contract_names_each_violation(tmp_path):
    assert check_solution(tmp_path / "solution.py")[0] == "f05.no_solution"
    big = _solution(tmp_path, "#" * (SOLUTION_MAX_BYTES + 1))
    assert check_solution(big)[0] == "f05.solution_too_large"
    assert check_solution(_solution(tmp_path, b"x = '\xff'\n"))[0] == "f05.solution_encoding"
    assert check_solution(MEAN_ACTION) is None


@pytest.mark.parametrize(
    "source, code",
    [
        ("def train(d):\n    pass\n", "f05.entry_point"),
        ("def train(d):\n    pass\n\ndef serve(s):\n    pass\n", "f05.no_checkpoint"),
        (
            "def train(d):\n    raise ValueError('bad batch')\n\ndef serve(s):\n    pass\n",
            "sandbox.exception",
        ),
        ("import time\n\ndef train(d):\n    time.sleep(30)\n\ndef serve(s):\n    pass\n", "sandbox.timeout"),
    ],
)
def test_training_faults_are_named(tmp_path, demos, source, code):
    fault = train(_solution(tmp_path, source), demos, tmp_path / "out", budget_s=3.0)
    assert fault is not None and fault[0] == code, fault


def test_training_sees_the_demonstrations_and_keeps_only_its_checkpoint(tmp_path, demos):
    assert train(MEAN_ACTION, demos, tmp_path / "out") is None
    with open(tmp_path / "out" / CKPT, "rb") as f:
        mean = np.load(f)
    assert np.allclose(mean, 0.2)  # mean of 0.1 and 0.3 over both episodes


def test_the_mean_action_baseline_replays_and_fails_on_a_partial_run(demos, libero10_task0_rendered):
    envs = {0: libero10_task0_rendered}
    res = replay(MEAN_ACTION, demos, [(0, 0)], requested=500, max_steps=16, envs=envs)
    assert res.fault is None and len(res.episodes) == 1
    (ep,) = res.episodes
    assert ep.steps == 16 and ep.requests == 2 and not ep.success and ep.fault == ""
    assert res.partial and res.success_rate == 0.0


def test_development_episodes_are_metered_in_a_sealed_ledger(tmp_path, demos, libero10_task0_rendered):
    from rle_design.errors import RleError
    from rle_design.ledger import verify_ledger
    from rle_tasks.envs.libero.dev import TASK_ID, DevelopmentClient

    served = tmp_path / "served"
    assert train(MEAN_ACTION, demos, served) is None
    (served / "solution.py").write_bytes(MEAN_ACTION.read_bytes())
    key = b"k" * 32
    dev = DevelopmentClient(tmp_path / "dev.jsonl", key, budget=3)
    envs = {0: libero10_task0_rendered}
    res = dev.evaluate(served, [(0, 0), (0, 1)], max_steps=8, envs=envs)
    assert [r.steps for r in res] == [8, 8] and dev.used == 2
    with pytest.raises(RleError) as exc:  # 2 more would pass the budget of 3: nothing runs
        dev.evaluate(served, [(0, 2), (0, 3)], max_steps=8, envs=envs)
    assert exc.value.code == "f05.budget_exhausted" and dev.used == 2
    dev.close()
    verdict = verify_ledger(tmp_path / "dev.jsonl", key, TASK_ID)
    assert verdict.valid and verdict.steps == 2 and verdict.opened["budget_episodes"] == 3
    assert not verify_ledger(tmp_path / "dev.jsonl", b"x" * 32, TASK_ID).valid
