"""Index provenance: a score from a reduced evaluation (quick mode, an episode subset) is marked partial
in its report, and the RLE Index takes it only on purpose, saying so."""

import pytest

from rle_design.errors import RleError
from rle_tasks.core.index import compute_index, format_tables
from rle_tasks.core.registry import get_task
from rle_tasks.core.results_page import write_index_html
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.core.solutions import materialise
from rle_tasks.core.task import VerifyContext
from rle_tasks.core.verify import run_verify

FULL = {"task_id": "08-mobile-base", "score": 0.8, "partial": False}
QUICK = {"task_id": "05-libero-open", "score": 0.5, "partial": True}


def test_a_quick_verification_is_marked_partial():
    task = get_task("09-gello")
    ref = materialise(task, "reference")
    ctx = VerifyContext(secret=Secret(PUBLIC_KEY, public=True), quick=True)
    report, _ = run_verify(task, ref, ctx)
    assert report.partial is True and report.to_dict()["partial"] is True


def test_the_index_refuses_partial_scores_unless_asked_and_then_names_them(tmp_path):
    with pytest.raises(RleError) as err:
        compute_index([FULL, QUICK])
    assert err.value.code == "index.partial" and "05-libero-open" in str(err.value)
    result = compute_index([FULL, QUICK], allow_partial=True)
    assert result.partial == ("05-libero-open",) and result.to_dict()["partial"] == ["05-libero-open"]
    assert result.task_scores["05-libero-open"] == 0.5
    text = format_tables(result)
    assert (
        "(includes partial scores)" in text
        and "partial (1 tasks, reduced evaluation): 05-libero-open" in text
    )
    page = write_index_html([result], tmp_path / "index.html").read_text()
    assert "<h2>Partial scores</h2>" in page and "05-libero-open" in page
    assert compute_index([FULL]).partial == () and "partial" not in format_tables(compute_index([FULL]))


def test_a_quick_verification_of_a_recorded_ledger_is_not_partial():
    """03's verifier replays the recorded session whatever the mode: nothing is reduced."""
    task = get_task("03-cantilever")
    assert not task.quick_reduces and get_task("01-open-fridge-l3").quick_reduces is False
    report, _ = run_verify(
        task,
        materialise(task, "reference"),
        VerifyContext(secret=Secret(PUBLIC_KEY, public=True), quick=True),
    )
    assert report.partial is False and report.score > 0.8


def test_the_page_shows_each_familys_native_diagnostics(tmp_path):
    reports = [
        {**FULL, "native_metrics": {"clearance_pct": 98.33, "piles": {"pile1": {}}, "quick": False}},
        {
            "task_id": "07-bin-clearing",
            "score": 0.8,
            "native_metrics": {"clearance_pct": 98.3, "parts_per_min": 7.466},
        },
    ]
    result = compute_index(reports)
    assert result.native["07-bin-clearing"] == {"clearance_pct": 98.3, "parts_per_min": 7.466}
    assert result.native["08-mobile-base"] == {"clearance_pct": 98.33}  # no nested tables, no bookkeeping
    page = write_index_html([result], tmp_path / "index.html").read_text()
    assert "<h2>Family results</h2>" in page and "id='f07'" in page and "<td>7.466</td>" in page
    assert result.diagnostics["07-bin-clearing"] == {"clearance [%]": 98.3, "parts/min": 7.466}
    assert page.index("id='f07'") < page.index("id='f08'")
