"""The card's score, pinned by hand-computed cases."""

import pytest

from rle_tasks.f07_bin_clearing.scoring import RUBRIC, h, pile_score, pile_terms, rubric, throughput


def _summary(cleared, n=12, makespan=120.0, floor=0, damage=0, bins=0):
    return {
        "n_parts": n,
        "cleared": cleared,
        "makespan_s": makespan,
        "N_floor": floor,
        "N_damage": damage,
        "N_bin": bins,
    }


def test_h_curve_hand_values():
    assert h(0.0) == 0.0
    assert h(0.6) == pytest.approx(0.1)  # 0.6 / 6
    assert h(0.3) == pytest.approx(0.05)  # 0.3 / 6
    assert h(0.8) == pytest.approx(0.1 + 0.9 * 0.5**3)  # (0.8 - 0.6) / 0.4 = 0.5 -> 0.2125
    assert h(1.0) == pytest.approx(1.0)


def test_throughput_uses_the_episode_length_when_incomplete():
    assert throughput(12, 60.0) == pytest.approx(12.0)  # 12 parts cleared in one minute
    assert pile_terms(_summary(6))["p"] == pytest.approx(3.0)  # incomplete: 6 parts / 2 min


def test_clean_complete_clear_in_72_s():
    # 12 parts in 72 s: p = 10/min; s = 0.30 + 0.35 h(1) + 0.20 min(1, 1) + 0.15 min(10/15, 1)
    s = pile_score(_summary(12, makespan=72.0))
    assert s == pytest.approx(0.30 + 0.35 + 0.20 + 0.15 * 10 / 15)


def test_events_remove_points_and_the_indicator():
    # complete in 72 s with one floor drop and one bin impact: I = 0
    s = pile_score(_summary(12, makespan=72.0, floor=1, bins=1))
    assert s == pytest.approx(0.35 + 0.20 - 0.03 - 0.05)
    t = pile_terms(_summary(12, makespan=72.0, floor=1, bins=1))
    assert t["complete"] == 0.0 and t["clean_throughput"] == 0.0


def test_partial_clear_and_clip_at_zero():
    # 9 of 12 in 120 s: f = 0.75, h = 0.1 + 0.9 (0.375)^3, p = 4.5/min
    want = 0.35 * (0.1 + 0.9 * 0.375**3) + 0.20 * 0.45
    assert pile_score(_summary(9)) == pytest.approx(want)
    assert pile_score(_summary(0, damage=3)) == 0.0


def test_rubric_report_equals_mean_of_pile_scores():
    piles = [_summary(12, makespan=72.0), _summary(9), _summary(0, damage=2)]
    rub = rubric(3)
    from rle_tasks.core.scoring import Outcome

    terms = [pile_terms(p) for p in piles]
    outcomes = {
        k: Outcome({v: t[k] for v, t in zip(rub.variants, terms)})
        for k in ("complete", "clearance", "throughput", "clean_throughput")
    }
    rep = rub.report(
        outcomes, valid=True, deductions={v: t["deduction"] for v, t in zip(rub.variants, terms)}
    )
    assert rep.score == pytest.approx(sum(pile_score(p) for p in piles) / 3)
    assert len(RUBRIC.variants) == 8
