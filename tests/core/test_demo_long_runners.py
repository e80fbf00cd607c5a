"""`rle demo` lists the solutions that exist to run out a long time limit instead of running them,
unless --full (family 05's over_budget sleeps out its 1,920 s training limit by design)."""

from rle_tasks import demo
from rle_tasks.core.registry import get_task
from rle_tasks.core.report import VerifierReport


def test_the_long_runners_are_declared_with_their_limit():
    assert demo.long_runners(get_task("05-libero-open")) == {"baseline/over_budget": 1920.0}
    assert demo.long_runners(get_task("08-mobile-base")) == {}


def test_the_default_demo_lists_them_and_the_full_demo_runs_them(tmp_path, monkeypatch):
    ran = []

    def fake_verify(task, directory, ctx):
        ran.append(directory.name)
        return VerifierReport(task_id=task.id, family="", workflow=""), False

    monkeypatch.setattr(demo, "materialise", lambda task, name: tmp_path / name.replace("/", "_"))
    monkeypatch.setattr(demo, "run_verify", fake_verify)
    task = get_task("05-libero-open")
    demo._verify_all(tmp_path / "out", quick=True, jobs=1, tasks=[task.id])
    assert "baseline_over_budget" not in ran and len(ran) == len(task.solutions) - 1
    assert [(t, n) for t, n, why in demo.not_run if "1920 s limit" in why] == [
        (task.id, "baseline/over_budget")
    ]
    ran.clear()
    demo._verify_all(tmp_path / "out", quick=True, jobs=1, tasks=[task.id], full=True)
    assert "baseline_over_budget" in ran and not demo.not_run
