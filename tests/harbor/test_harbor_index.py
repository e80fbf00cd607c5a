"""``rle index`` on a Harbor job directory built here: two systems, three tasks, one failed trial.

Trials (reward, cost USD, input/cached/output tokens, wall time):

    claude-code (claude-opus-4-5): 08 0.8 $2 1000/400/100 1 h; 09 0.4 $1 3000/1000/300 0.5 h;
                                   F06 0.6 $3 2000/600/200 2 h
    codex (gpt-5):                 08 0.5 $0.5 500/100/50 0.25 h; 09 failed (AgentTimeoutError, no
                                   reward) $1.5 1500/500/150 0.75 h; 09 again 0.3 $1 1000/200/100 0.5 h

Index by hand (eq. 1; n06 = registered F06 tasks, F07 scores 0, other workflows 0):
    claude: mechanical (0.8 + 0.4)/2 = 0.6; perception (0.6/n06 + 0)/2; index = (perception + 0.6)/4
    codex:  F09 = (0 + 0.3)/2 = 0.15; mechanical (0.5 + 0.15)/2 = 0.325; index = 0.325/4 = 0.08125
Resources (means through task -> family -> workflow, as the index; totals over trials):
    claude: cost per task 08 2, 09 1, F06 3 -> mechanical (2 + 1)/2 = 1.5, perception 3 -> mean 2.25;
            hours 08 1, 09 0.5, F06 2 -> (0.75 + 2)/2 = 1.375; total $6; tokens 6000/2000/600
    codex:  cost 08 0.5, 09 (1.5 + 1)/2 = 1.25 -> mechanical 0.875 (its only workflow) -> 0.875;
            hours 08 0.25, 09 (0.75 + 0.5)/2 = 0.625 -> 0.4375; total $3; tokens 3000/800/300
"""

from __future__ import annotations

import base64
import json
from datetime import UTC, datetime, timedelta

import pytest

from rle_tasks.core.export.harbor.results import read_job, systems
from rle_tasks.core.registry import all_tasks
from rle_tasks.core.results import index_command

T0 = datetime(2026, 11, 22, 8, 0, tzinfo=UTC)


def _trial(job, name, agent, model, task, reward, cost, tokens, hours, exception=None):
    data = {
        "id": "00000000-0000-0000-0000-000000000000",
        "task_name": f"rle-bench/{task}",
        "trial_name": name,
        "trial_uri": f"file://{job / name}",
        "agent_info": {"name": agent, "version": "1.0", "model_info": {"name": model, "provider": "x"}},
        "agent_result": {
            "n_input_tokens": tokens[0],
            "n_cache_tokens": tokens[1],
            "n_output_tokens": tokens[2],
            "cost_usd": cost,
        },
        "verifier_result": {"rewards": {"reward": reward, "secret_private": 1}}
        if reward is not None
        else None,
        "exception_info": exception,
        "started_at": T0.isoformat(),
        "finished_at": (T0 + timedelta(hours=hours)).isoformat().replace("+00:00", "Z"),
    }
    (job / name).mkdir()
    (job / name / "result.json").write_text(json.dumps(data))


@pytest.fixture
def job(tmp_path):
    job = tmp_path / "job"
    job.mkdir()
    (job / "result.json").write_text(json.dumps({"id": "job", "n_total_trials": 6}))  # the job's own
    f06 = next(t.id for t in all_tasks() if t.family == 6)
    a, b = ("claude-code", "claude-opus-4-5"), ("codex", "gpt-5")
    _trial(job, "a1", *a, "08-mobile-base", 0.8, 2.0, (1000, 400, 100), 1.0)
    _trial(job, "a2", *a, "09-gello", 0.4, 1.0, (3000, 1000, 300), 0.5)
    _trial(job, "a3", *a, f06, 0.6, 3.0, (2000, 600, 200), 2.0)
    _trial(job, "b1", *b, "08-mobile-base", 0.5, 0.5, (500, 100, 50), 0.25)
    timeout = {
        "exception_type": "AgentTimeoutError",
        "exception_message": "agent ran past 7200 s",
        "exception_traceback": "",
        "occurred_at": T0.isoformat(),
    }
    _trial(job, "b2", *b, "09-gello", None, 1.5, (1500, 500, 150), 0.75, timeout)
    _trial(job, "b3", *b, "09-gello", 0.3, 1.0, (1000, 200, 100), 0.5)
    return job


def test_index_per_system_and_resources(job):
    n06 = sum(t.family == 6 for t in all_tasks())
    out = systems(read_job(job))
    assert list(out) == ["claude-code (claude-opus-4-5)", "codex (gpt-5)"]
    claude, claude_res = out["claude-code (claude-opus-4-5)"]
    codex, codex_res = out["codex (gpt-5)"]
    assert claude.workflow_scores["mechanical_design"] == pytest.approx(0.6, abs=1e-12)
    assert claude.workflow_scores["perception_estimation"] == pytest.approx(0.6 / n06 / 2, abs=1e-12)
    assert claude.index == pytest.approx((0.6 / n06 / 2 + 0.6) / 4, abs=1e-12)
    assert codex.task_scores["09-gello"] == pytest.approx(0.15, abs=1e-12)
    assert codex.index == pytest.approx(0.08125, abs=1e-12)
    f06 = next(t.id for t in all_tasks() if t.family == 6)
    assert claude.task_scores[f06] == 0.6 and f06 not in claude.missing and f06 in codex.missing
    assert len(codex.missing) == len(all_tasks()) - 2  # 08 and 09 reached; the rest count 0
    assert (claude_res.trials, claude_res.failed, claude_res.tasks, claude_res.cost_runs) == (3, 0, 3, 3)
    assert claude_res.mean_cost_usd == pytest.approx(2.25) and claude_res.total_cost_usd == pytest.approx(6.0)
    assert claude_res.mean_elapsed_h == pytest.approx(1.375)
    assert (claude_res.input_tokens, claude_res.cached_tokens, claude_res.output_tokens) == (6000, 2000, 600)
    assert (codex_res.trials, codex_res.failed, codex_res.tasks, codex_res.cost_runs) == (3, 1, 2, 3)
    assert codex_res.mean_cost_usd == pytest.approx(0.875) and codex_res.total_cost_usd == pytest.approx(3.0)
    assert codex_res.mean_elapsed_h == pytest.approx(0.4375)
    assert (codex_res.input_tokens, codex_res.cached_tokens, codex_res.output_tokens) == (3000, 800, 300)
    assert codex_res.failed_trials == ("09-gello/b2: AgentTimeoutError: agent ran past 7200 s",)


def test_rle_index_command_on_a_job_directory(job, tmp_path, capsys):
    page = tmp_path / "index.html"
    assert index_command([str(job)], html=page) == 0
    text = capsys.readouterr().out
    assert "RLE Index for claude-code (claude-opus-4-5)" in text and "RLE Index for codex (gpt-5)" in text
    assert f"{'RLE Index':<32}{100 * 0.08125:>8.1f}%" in text
    assert "failed (codex (gpt-5)): 09-gello/b2: AgentTimeoutError: agent ran past 7200 s" in text
    html = page.read_text()
    assert (
        "<td>codex (gpt-5)</td><td>0.88</td><td>3.00</td><td>3/3</td><td>0.44</td><td>0.00</td><td>0.00</td>"
        "<td>0.00</td><td>2</td><td>1</td>" in html
    )
    assert "<td>claude-code (claude-opus-4-5)</td><td>2.25</td><td>6.00</td><td>3/3</td><td>1.38</td>" in html
    assert "<li>codex (gpt-5): 09-gello/b2: AgentTimeoutError: agent ran past 7200 s</li>" in html
    for alt in ("leaderboard", "capability profile", "performance versus cost"):
        png = html.split(f'<img alt="{alt}" src="data:image/png;base64,', 1)[1].split('"', 1)[0]
        assert base64.b64decode(png)[:8] == b"\x89PNG\r\n\x1a\n"


def test_plain_reports_and_errors(job, tmp_path, capsys):
    from rle_tasks.core.report import VerifierReport

    report = tmp_path / "r.json"
    VerifierReport("08-mobile-base", "08", "", score=1.0, valid=True).write(report)
    assert index_command([str(report), str(job)], name="mine") == 0
    assert "RLE Index for mine" in capsys.readouterr().out
    empty = tmp_path / "empty"
    empty.mkdir()
    assert index_command([str(empty)]) == 2
    assert "is a directory; pass the report files" in capsys.readouterr().err


def test_cost_coverage_counts_only_trials_whose_agent_reported_a_cost(tmp_path):
    job = tmp_path / "j"
    job.mkdir()
    _trial(job, "x1", "terminus", "m", "08-mobile-base", 0.5, 2.0, (10, 0, 1), 1.0)
    _trial(job, "x2", "terminus", "m", "09-gello", 0.5, None, (10, 0, 1), 1.0)  # the harness reports none
    (_, res), *_ = systems(read_job(job)).values()
    assert (res.cost_runs, res.trials, res.total_cost_usd) == (1, 2, 2.0)
    assert res.mean_cost_usd == pytest.approx(
        1.0
    )  # an unreported cost counts 0 in the mean: coverage says so
