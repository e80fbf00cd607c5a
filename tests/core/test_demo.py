"""``rle demo`` verifies every shipped solution from its materialised directory (verifier stubbed)."""

from __future__ import annotations

import html

from rle_tasks import demo, demo_checks, demo_progress
from rle_tasks.core.registry import all_tasks, get_task
from rle_tasks.core.report import VerifierReport, artifact_sha256
from rle_tasks.core.solutions import declaration


def test_demo_verifies_every_shipped_solution_from_its_materialised_directory(tmp_path, monkeypatch):
    seen = []

    def fake_verify(task, directory, ctx):
        seen.append((task.id, directory))
        return VerifierReport(task.id, f"{task.family:02d}", task.workflow, score=0.5, valid=True), False

    monkeypatch.setattr(demo, "run_verify", fake_verify)
    results = demo._verify_all(tmp_path, quick=True, jobs=1)
    expected = [
        (t.id, n) for t in all_tasks() if t.implemented for n in t.solutions if n not in demo.long_runners(t)
    ]
    assert [(tid, name) for tid, name, _, _ in results] == expected and len(expected) >= 10
    for (tid, directory), (_, name, report_path, _) in zip(seen, results):
        assert artifact_sha256(directory) == declaration(get_task(tid)).get(name).sha256
        assert report_path.is_file()


def test_demo_verifies_references_in_full_and_baselines_quick_unless_asked(tmp_path, monkeypatch):
    """Tasks scored over a fixed episode set (hours of simulation) always run their quick subset."""
    modes: dict[str, list[bool]] = {}

    def fake_verify(task, directory, ctx):
        modes.setdefault("seen", []).append(ctx.quick)
        return VerifierReport(task.id, f"{task.family:02d}", task.workflow, score=0.5, valid=True), False

    monkeypatch.setattr(demo, "run_verify", fake_verify)
    results = demo._verify_all(tmp_path, quick=False, jobs=1)
    scored = {t.id for t in all_tasks() if t.episode_scored}
    assert scored == {"05-libero-open", "05-libero-robust", "05-robotwin-open", "05-robotwin-robust"}
    expected = [name != "reference" or tid in scored for tid, name, _, _ in results]
    assert modes["seen"] == expected and any(expected) and not all(expected)
    modes.clear()
    demo._verify_all(tmp_path, quick=False, jobs=1, full_baselines=True)
    assert modes["seen"] == [tid in scored for tid, _, _, _ in results]
    modes.clear()
    demo._verify_all(tmp_path, quick=True, jobs=1)
    assert modes["seen"] == [True] * len(expected)


def test_demo_lists_what_the_operators_set_up_lacks_instead_of_failing(tmp_path, monkeypatch):
    from rle_tasks.core.verify import VerifierSetupError

    def fake_verify(task, directory, ctx):
        if task.family == 5:
            raise VerifierSetupError("the demonstration dataset is not built: make libero-demos")
        return VerifierReport(task.id, f"{task.family:02d}", task.workflow, score=0.5, valid=True), False

    monkeypatch.setattr(demo, "run_verify", fake_verify)
    results = demo._verify_all(tmp_path, quick=True, jobs=1)
    assert all(not tid.startswith("05-") for tid, _, _, _ in results)
    assert {(t, n) for t, n, _ in demo.not_run} == {
        (t, n)
        for t in ("05-libero-open", "05-libero-robust", "05-robotwin-open", "05-robotwin-robust")
        for n in get_task(t).solutions
    }
    page = demo.write_html(tmp_path, results, [], None, 1.0).read_text()
    lacking = [why for _, _, why in demo.not_run if "make libero-demos" in why]
    assert page.count("make libero-demos") == len(lacking) == len(demo.not_run) - 1  # over_budget: its limit
    assert page.count("`rle demo --full` runs it") == 1


def test_demo_marks_quick_scores_that_differ_from_their_golden_scores(tmp_path):
    """Only reports made in quick mode with the public key are compared: a golden score is pinned in
    that mode; a full-mode score or one under another secret has nothing to be compared with."""
    task = get_task("09-gello")
    golden = declaration(task).get("reference").quick_score

    def report(score, secret="public"):
        return VerifierReport(task.id, "09", task.workflow, score=score, valid=True, secret=secret)

    path = tmp_path / "r.json"
    results = [
        (task.id, "reference", path, report(golden)),
        (task.id, "baseline/uncompensated", path, report(0.999)),
        (task.id, "baseline/over_mass", path, report(0.999, secret="operator")),
        (task.id, "baseline/hanging_trim", path, report(0.999)),
    ]
    modes = {(task.id, n): True for _, n, _, _ in results} | {(task.id, "baseline/hanging_trim"): False}
    differs = demo_checks.golden_differences(results, modes)
    uncompensated = declaration(task).get("baseline/uncompensated").quick_score
    assert differs == {(task.id, "baseline/uncompensated"): uncompensated}
    page = demo.write_html(tmp_path, results, [], None, 1.0, modes, differs).read_text()
    assert page.count("(golden ") == 1 and f"(golden {uncompensated:.3f})" in page


def test_the_full_demo_compares_full_reports_with_pinned_full_scores_and_names_retrainings(
    tmp_path, monkeypatch
):
    """A full report is compared with its golden score in ``FULL_GOLDENS`` where one is pinned
    (counted as unpinned otherwise); a report that trained a recipe says whether its checkpoint
    reproduced the pinned one; ``full_scores`` is what pins them."""
    import json

    task = get_task("09-gello")
    goldens = tmp_path / "full_goldens.json"
    goldens.write_text(json.dumps({f"{task.id}:reference": 0.8}))
    monkeypatch.setattr(demo_checks, "FULL_GOLDENS", goldens)

    def report(score, secret="public", **native):
        return VerifierReport(
            task.id, "09", task.workflow, score=score, valid=True, secret=secret, native_metrics=native
        )

    path = tmp_path / "r.json"
    results = [
        (task.id, "reference", path, report(0.8 + 2e-6, training="trained", ckpt_reproduced=True)),
        (task.id, "baseline/uncompensated", path, report(0.1, training="trained", ckpt_reproduced=False)),
        (task.id, "baseline/over_mass", path, report(0.0, training="trained")),
        (task.id, "baseline/hanging_trim", path, report(0.5, secret="operator", training="shipped")),
    ]
    modes = {(task.id, n): False for _, n, _, _ in results}
    assert demo_checks.golden_differences(results, modes) == {(task.id, "reference"): 0.8}  # 2e-6 > 1e-6
    assert demo_checks.full_scores(results, modes) == {
        f"{task.id}:reference": 0.8 + 2e-6,
        f"{task.id}:baseline/uncompensated": 0.1,
        f"{task.id}:baseline/over_mass": 0.0,
    }  # the operator-secret report pins nothing
    results[0] = (task.id, "reference", path, report(0.8 + 5e-7))
    assert demo_checks.golden_differences(results, modes) == {}
    assert demo_checks.unpinned_full(results, modes) == [(task.id, n) for _, n, _, _ in results[1:]]
    assert demo_checks.retrainings(results) == [
        (task.id, "baseline/uncompensated", False),
        (task.id, "baseline/over_mass", None),
    ]
    page = demo.write_html(tmp_path, results, [], None, 1.0, modes, {}).read_text()
    assert page.count("checkpoint differs") == 1 and page.count("shipped checkpoint") == 1
    goldens.write_text("not json")
    assert demo_checks.full_goldens() == {}


def test_demo_runs_the_tasks_it_is_given_by_id_or_family_number(tmp_path, monkeypatch):
    import pytest

    from rle_design.errors import RleError

    seen = []

    def fake_verify(task, directory, ctx):
        seen.append(task.id)
        return VerifierReport(task.id, f"{task.family:02d}", task.workflow, score=0.5, valid=True), False

    monkeypatch.setattr(demo, "run_verify", fake_verify)
    assert [t.id for t in demo.select_tasks(["05", "09-gello"])] == [
        "05-libero-open",
        "05-libero-robust",
        "05-robotwin-open",
        "05-robotwin-robust",
        "09-gello",
    ]
    demo._verify_all(tmp_path, quick=True, jobs=1, tasks=["09-gello"])
    assert seen == ["09-gello"] * len(get_task("09-gello").solutions)
    for pattern in ("9-gello", "04-run", "10"):  # a typo, a registered task without a verifier, no family
        with pytest.raises(RleError, match="names no implemented task") as err:
            demo.select_tasks([pattern])
        assert "09-gello" in str(err.value)
    page = demo.write_html(tmp_path, [], [], None, 1.0, subset=["09-gello"]).read_text()
    assert "selected tasks only (09-gello" in page
    assert "every implemented task" in demo.write_html(tmp_path, [], [], None, 1.0).read_text()


def test_the_quick_demo_says_what_it_shortened_and_the_full_demo_trains(tmp_path, monkeypatch):
    """``rle demo`` runs every solution quick and reuses cached trainings; ``--full`` does neither."""
    seen = {}

    def fake_verify(task, directory, ctx):
        seen.setdefault(task.id, set()).add((ctx.quick, ctx.reuse_training))
        native = {"training": "reused"} if task.family == 5 and ctx.reuse_training else {}
        return VerifierReport(
            task.id, f"{task.family:02d}", task.workflow, valid=True, native_metrics=native
        ), False

    monkeypatch.setattr(demo, "run_verify", fake_verify)
    monkeypatch.setattr(demo, "render_arms", lambda out: [])
    from rle_tasks.cli import main

    assert main(["demo", "--out", str(tmp_path / "q"), "--task", "09", "--task", "05-robotwin-open"]) == 0
    assert seen == {"05-robotwin-open": {(True, True)}, "09-gello": {(True, True)}}
    page = (tmp_path / "q" / "index.html").read_text()
    assert "Every solution runs in quick mode" in page and "cached training" in page
    assert "<h2>What quick mode runs</h2>" in page and html.escape(get_task("09-gello").quick_note) in page
    seen.clear()
    assert (
        main(["demo", "--out", str(tmp_path / "f"), "--task", "09", "--task", "05-robotwin-open", "--full"])
        == 0
    )
    # the reference in full, baselines quick; 05's episodes stay quick (hours in full), its recipes retrain
    assert seen == {"05-robotwin-open": {(True, False)}, "09-gello": {(False, False), (True, False)}}
    page = (tmp_path / "f" / "index.html").read_text()
    assert "References run the full batteries" in page and "What quick mode runs" not in page


def test_progress_estimates_the_time_left_per_family_from_the_measured_times(tmp_path, monkeypatch):
    """Times 60 s (08 reference) and 120 s (09 reference), 30 s for an unlisted artifact (the mean of
    the listed ones would be 90 s; with none listed 30 s). After the 08 reference took 120 s (twice
    its time), what is left is scaled by 2: F09 2 x (120 + 90) s = 7 min."""
    times = tmp_path / "times.json"
    times.write_text('{"quick:08-mobile-base:reference": 60, "quick:09-gello:reference": 120}')
    monkeypatch.setattr(demo_progress, "DEMO_TIMES", times)
    t08, t09 = get_task("08-mobile-base"), get_task("09-gello")
    clock = demo_progress.Estimate([(t08, "reference"), (t09, "reference"), (t09, "baseline/x")], full=False)
    assert clock.left(9) == "F09 ~3.5 min left, all ~4.5 min"  # 120 + 90 s of F09; 270 s in all
    clock.done(t08, "reference", 120.0)
    assert clock.left(9) == "F09 ~7.0 min left, all ~7.0 min"  # (120 + 90) x 2
    clock.write(tmp_path / "out.json")
    assert (
        (tmp_path / "out.json").read_text().strip().startswith('{\n "quick:08-mobile-base:reference": 120.0')
    )


def test_every_reference_the_full_demo_verifies_in_full_has_a_pinned_full_golden_score():
    """``full_goldens.json`` pins exactly the references that ``rle demo --full`` runs in full (the
    episode-scored tasks run their quick subset there too), each a score in [0, 1]."""
    goldens = demo_checks.full_goldens()
    expected = {
        f"{t.id}:reference"
        for t in all_tasks()
        if t.implemented
        and "reference" in t.solutions
        and not demo._mode("reference", False, False, t.episode_scored)
    }
    assert set(goldens) == expected and len(expected) >= 20
    assert all(0.0 <= s <= 1.0 for s in goldens.values())
