"""RLE Index (paper eq. 1): golden value, missing tasks, input errors, tables and the HTML page."""

import base64
import json

import pytest

from rle_design.errors import RleError
from rle_tasks.core.index import compute_index, format_tables
from rle_tasks.core.registry import all_tasks
from rle_tasks.core.report import VerifierReport
from rle_tasks.core.results import index_command
from rle_tasks.core.task import WORKFLOW_ORDER


def _report(task_id: str, score: float) -> VerifierReport:
    fam = int(task_id[:2])
    return VerifierReport(task_id=task_id, family=f"{fam:02d}", workflow="", score=score, valid=True)


def _write(tmp_path, task_id: str, score: float, name: str | None = None):
    p = tmp_path / (name or f"{task_id}.json")
    _report(task_id, score).write(p)
    return p


GOLDEN = {"08-mobile-base": 0.6, "09-gello": 0.4, "06-pose-a-rgb": 0.8}


def test_golden_index_is_exactly_0_15():
    res = compute_index([_report(t, s) for t, s in GOLDEN.items()])
    # F08 = .6, F09 = .4 -> mechanical (.6 + .4)/2 = .5; F06 = (.8 + 0 + 0 + 0)/4 = .2, F07 = 0 ->
    # perception .1; interactive and policy 0 -> index (0 + 0 + .1 + .5)/4 = .15.
    assert res.family_scores[8] == 0.6 and res.family_scores[9] == 0.4
    assert res.family_scores[6] == 0.2 and res.family_scores[7] == 0.0
    assert res.workflow_scores == {
        "interactive_control": 0.0,
        "policy_learning": 0.0,
        "perception_estimation": 0.1,
        "mechanical_design": 0.5,
    }
    assert res.index == 0.15
    assert len(res.missing) == len(all_tasks()) - 3
    assert "06-pose-b-rgbd" in res.missing and "08-mobile-base" not in res.missing
    assert list(res.workflow_scores) == list(WORKFLOW_ORDER)


def test_order_and_input_kind_do_not_matter(tmp_path):
    files = [_write(tmp_path, t, s) for t, s in GOLDEN.items()]
    dicts = [_report(t, s).to_dict() for t, s in reversed(GOLDEN.items())]
    assert compute_index(files).index == compute_index(dicts).index == 0.15
    assert compute_index([str(files[0]), dicts[1], _report("06-pose-a-rgb", 0.8)]).index == 0.15


def test_all_ones_give_one_and_nothing_gives_zero():
    full = compute_index([_report(t.id, 1.0) for t in all_tasks()])
    assert full.index == 1.0 and full.missing == ()
    empty = compute_index([])
    assert empty.index == 0.0 and len(empty.missing) == len(all_tasks())


def test_family_mean_counts_every_registered_task():
    # 15 tasks in F01: one perfect report gives F01 = 1/15 and interactive = (1/15)/3.
    res = compute_index([_report("01-open-fridge-l1", 1.0)])
    assert res.family_scores[1] == pytest.approx(1 / 15, rel=1e-15)
    assert res.workflow_scores["interactive_control"] == pytest.approx(1 / 45, rel=1e-15)
    assert res.index == pytest.approx(1 / 180, rel=1e-15)


def test_duplicate_report_is_an_error(tmp_path):
    a = _write(tmp_path, "09-gello", 0.4, "a.json")
    b = _write(tmp_path, "09-gello", 0.5, "b.json")
    with pytest.raises(RleError) as exc:
        compute_index([a, b])
    assert str(exc.value) == f"two reports for task '09-gello': {a} and {b}; pass one report per task"
    assert exc.value.code == "index.duplicate"


def test_unknown_task_is_an_error():
    with pytest.raises(RleError) as exc:
        compute_index([_report("09-gelo", 0.4)])
    assert str(exc.value) == "report #0 names unknown task '09-gelo'. Known ids: 09-gello"
    assert exc.value.code == "index.unknown_task"


def test_bad_inputs_name_the_file(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    with pytest.raises(RleError, match=rf"report file {bad} is not JSON: "):
        compute_index([bad])
    other = tmp_path / "other.json"
    other.write_text(json.dumps({"score": 1.0}))
    with pytest.raises(RleError, match=rf"^{other} is not a verifier report \(no 'task_id' field\)$"):
        compute_index([other])
    with pytest.raises(RleError, match=r"^report #0 \(task '09-gello'\) has score 1.5, outside \[0, 1\]$"):
        compute_index([{"task_id": "09-gello", "score": 1.5}])
    with pytest.raises(RleError, match=rf"^{tmp_path} is a directory; pass the report files"):
        compute_index([tmp_path])


def test_tables_show_families_workflows_index_and_missing():
    res = compute_index([_report(t, s) for t, s in GOLDEN.items()], name="golden")
    text = format_tables(res)
    assert "RLE Index for golden" in text
    assert "F06     perception_estimation          1/4    20.0%" in text
    assert "F08     mechanical_design              1/1    60.0%" in text
    assert "mechanical_design                   50.0%" in text
    assert "RLE Index                           15.0%" in text
    assert f"missing ({len(all_tasks()) - 3} tasks, scored 0):" in text
    assert "  F06: 06-pose-b-rgbd, 06-pose-c-learned, 06-pose-d-agnostic" in text


def test_index_command_writes_self_contained_html(tmp_path, capsys):
    files = [_write(tmp_path, t, s) for t, s in GOLDEN.items()]
    html = tmp_path / "out" / "index.html"
    assert index_command([str(f) for f in files], html=str(html), name="my <agent>") == 0
    out = capsys.readouterr().out
    assert "RLE Index                           15.0%" in out
    page = html.read_text()
    assert "my &lt;agent&gt;" in page and "<agent>" not in page
    images = page.split('src="data:image/png;base64,')[1:]
    assert len(images) == 2  # leaderboard and capability profile
    for img in images:
        png = base64.b64decode(img.split('"', 1)[0])
        assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 5000
    assert "<td>RLE Index</td><td>15.0</td>" in page
    assert "http" not in page.replace("http-equiv", "")  # nothing fetched from outside


def test_index_command_missing_file_exits_2(tmp_path, capsys):
    missing = tmp_path / "nope.json"
    assert index_command([str(missing)]) == 2
    err = capsys.readouterr().err
    assert err.strip() == f"rle index: error [index.input]: report file {missing} does not exist"


def test_cli_dispatches_index(tmp_path, capsys):
    from rle_tasks.cli import main

    f = _write(tmp_path, "08-mobile-base", 0.6)
    assert main(["index", str(f), "--name", "cli"]) == 0
    assert "RLE Index for cli" in capsys.readouterr().out
    assert main(["index", str(tmp_path / "x.json")]) == 2
