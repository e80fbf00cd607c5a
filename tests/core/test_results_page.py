"""The results page: each family's diagnostics from its reports (closed forms on hand-made reports),
and the page as a real browser renders it (headless Chromium: images decoded, sections, screenshot)."""

from __future__ import annotations

import json
import struct

import pytest

from rle_tasks.core.browser import find_browser, page_facts, screenshot
from rle_tasks.core.diagnostics import task_diagnostics
from rle_tasks.core.index import compute_index
from rle_tasks.core.report import VerifierReport
from rle_tasks.core.results import index_command
from rle_tasks.core.results_page import write_index_html


def _cp(cid: str, weight: float, score: float) -> dict:
    return {"id": cid, "weight": weight, "score": score, "passed": score > 0, "message": ""}


def _reports(scale: float) -> list[dict]:
    """04 on two clips, 07, 08 with its six checkpoints, 09 with three arms; ``scale`` in (0, 1]."""
    return [
        {
            "task_id": "04-dance",
            "score": 0.5 * scale,
            "native_metrics": {"mpjpe_mm": 40.0, "survival_pct": 90.0},
        },
        {
            "task_id": "04-fight",
            "score": 0.3 * scale,
            "native_metrics": {"mpjpe_mm": 60.0, "survival_pct": 70.0},
        },
        {
            "task_id": "07-bin-clearing",
            "score": 0.8 * scale,
            "native_metrics": {"clearance_pct": 93.3, "parts_per_min": 7.5, "piles": {}},
        },
        {
            "task_id": "08-mobile-base",
            "score": 0.7 * scale,
            "checkpoints": [
                _cp("validity", 0.15, 1.0),
                _cp("design_resources", 0.35, 0.6),
                _cp("static_stability", 0.15, 1.0),
                _cp("dynamic_stability", 0.2, 0.75),
                _cp("shelf_1kg", 0.1, 0.5),
                _cp("shelf_2kg", 0.05, 1.0 * scale),
            ],
        },
        {
            "task_id": "09-gello",
            "score": 0.6 * scale,
            "native_metrics": {
                "variant_score": {"panda": 0.6, "ur5e": 0.5, "xarm7": 0.7 * scale},
                "panda": {"device_mass_kg": 1.5},
                "ur5e": {"device_mass_kg": 1.2},
                "xarm7": {"device_mass_kg": 1.8},
            },
        },
    ]


def test_family_diagnostics_in_closed_form():
    d = {r["task_id"]: task_diagnostics(VerifierReport.from_dict(r)) for r in _reports(1.0)}
    assert d["04-dance"] == {"MPJPE [mm]": 40.0, "survival [%]": 90.0}
    assert d["07-bin-clearing"] == {"clearance [%]": 93.3, "parts/min": 7.5}
    # 08: credit / weight per stage; integration = (0.1 * 0.5 + 0.05 * 1.0) / 0.15 = 2/3
    s08 = d["08-mobile-base"]
    assert s08["validity [%]"] == pytest.approx(100.0) and s08["resources [%]"] == pytest.approx(60.0)
    assert s08["dynamic [%]"] == pytest.approx(75.0) and s08["integration [%]"] == pytest.approx(200 / 3)
    # 09: per-arm rewards in percent; mass = (1.5 + 1.2 + 1.8) / 3 = 1.5 kg
    assert d["09-gello"] == pytest.approx(
        {"panda [%]": 60.0, "ur5e [%]": 50.0, "xarm7 [%]": 70.0, "device mass [kg]": 1.5}
    )
    # a report the hook cannot read shows nothing and does not stop the index
    bad = VerifierReport.from_dict(
        {"task_id": "09-gello", "score": 0.1, "native_metrics": {"variant_score": 3}}
    )
    assert task_diagnostics(bad) == {}


def test_family_means_on_the_page(tmp_path):
    """The 04 row the paper's native table quotes: MPJPE (40 + 60)/2 = 50 mm, survival (90 + 70)/2 = 80 %."""
    result = compute_index(_reports(1.0), name="sys")
    page = write_index_html([result], tmp_path / "index.html").read_text()
    assert "<td>sys</td><td>family mean (2 tasks)</td><td>50</td><td>80</td>" in page
    assert "id='f04'" in page and "id='f05'" not in page  # only families with a report get a section


@pytest.mark.skipif(
    find_browser() is None, reason="no headless Chromium: bash scripts/apt-deps.sh installs one"
)
def test_page_in_a_real_browser(tmp_path):
    results = [compute_index(_reports(1.0), name="reference"), compute_index(_reports(0.5), name="other")]
    page = write_index_html(results, tmp_path / "index.html")
    facts = page_facts(page)
    # leaderboard, capability profile, and one figure per family section (04, 07, 08, 09): all decoded
    assert facts["images"] == facts["decoded"] == 2 + 4
    assert facts["h2"][:2] == ["Leaderboard", "Capability profile (per workflow)"]
    assert "Family results" in facts["h2"]
    sections = {s["id"]: s for s in facts["sections"]}
    assert sorted(sections) == ["f04", "f07", "f08", "f09"]
    assert sections["f04"]["columns"] == ["system", "task", "MPJPE [mm]", "survival [%]"]
    assert sections["f04"]["means"] == 2  # one family-mean row per system
    assert "integration [%]" in sections["f08"]["columns"]
    png = screenshot(page, tmp_path / "page.png", width=1000)
    data = png.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    assert struct.unpack(">II", data[16:24]) == (1000, facts["height"]) and facts["height"] > 2000


@pytest.mark.skipif(
    find_browser() is None, reason="no headless Chromium: bash scripts/apt-deps.sh installs one"
)
def test_rle_index_screenshot_of_a_harbor_job(tmp_path, capsys):
    """A job directory whose trials kept the verifier's report: the page shows its diagnostics."""
    job = tmp_path / "job"
    for i, report in enumerate(_reports(1.0)):
        trial = job / f"t{i}"
        (trial / "verifier").mkdir(parents=True)
        (trial / "verifier" / "report.json").write_text(json.dumps(report))
        (trial / "result.json").write_text(
            json.dumps(
                {
                    "task_name": f"rle-bench/{report['task_id']}",
                    "trial_name": f"t{i}",
                    "agent_info": {"name": "oracle"},
                    "verifier_result": {"rewards": {"reward": report["score"]}},
                }
            )
        )
    html, png = tmp_path / "page.html", tmp_path / "page.png"
    assert index_command([str(job)], html=html, screenshot=png) == 0
    assert "screenshot written" in capsys.readouterr().out
    assert "<td>oracle</td><td>family mean (2 tasks)</td><td>50</td><td>80</td>" in html.read_text()
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert index_command([str(job)], screenshot=png) == 2  # a screenshot needs the page
