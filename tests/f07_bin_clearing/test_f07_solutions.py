"""Shipped solutions: golden quick scores (public key) and the named reason each baseline fails for."""

import pytest

from rle_tasks.core.registry import get_task
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.core.solutions import declaration, materialise
from rle_tasks.core.task import VerifyContext
from rle_tasks.f07_bin_clearing.verifier import verify

TASK = get_task("07-bin-clearing")
SOLUTIONS = declaration(TASK)
pytestmark = pytest.mark.physics


def _verify(name):
    ctx = VerifyContext(secret=Secret(PUBLIC_KEY, public=True), quick=True, hang_cap_s=2.0)
    return verify(materialise(TASK, name), ctx)


REDUCED = ("reference", "baseline/bin_slammer", "baseline/raising", "baseline/hanging")
"""Solutions verified in the default (reduced) run; all of them with RLE_FULL_BATTERY=1."""


@pytest.fixture(scope="module")
def reports(full_battery):
    return {name: _verify(name) for name in (TASK.solutions if full_battery else REDUCED)}


def test_golden_quick_scores(reports):
    for name, rep in reports.items():
        assert rep.score == pytest.approx(SOLUTIONS.get(name).quick_score, abs=1e-9), name
        assert rep.native_metrics["partial"] is True


def test_reference_clears_without_events_in_the_quick_pile(reports):
    # 30 s of hidden pile 1: its first pick lifts two hooked brackets, which block the nest; the
    # reference lifts one out and delivers it later (the full evaluation is in the benchmark)
    pile = reports["reference"].native_metrics["piles"]["pile1"]
    ev = pile["events"]
    assert ev["cleared"] >= 1 and pile["fault"] is None
    assert ev["N_floor"] == ev["N_damage"] == ev["N_bin"] == 0


def test_baselines_fail_for_their_named_reason(reports):
    piles = {n: r.native_metrics.get("piles", {}).get("pile1") for n, r in reports.items()}
    if "baseline/idle" in reports:
        assert piles["baseline/idle"]["events"]["cleared"] == 0 and piles["baseline/idle"]["fault"] is None
    if "baseline/floor_dropper" in reports:
        assert piles["baseline/floor_dropper"]["events"]["N_floor"] >= 1
        assert piles["baseline/floor_dropper"]["events"]["cleared"] == 0
    assert piles["baseline/bin_slammer"]["events"]["N_bin"] >= 3
    for name, code in (("baseline/raising", "sandbox.exception"), ("baseline/hanging", "sandbox.timeout")):
        rep = reports[name]
        assert rep.cap == 0.1 and rep.score == 0.0
        assert any(e.code == code and "smoke test failed" in e.message for e in rep.errors), name
    for name, rep in reports.items():
        if name != "reference":
            assert rep.score < 0.05, name
