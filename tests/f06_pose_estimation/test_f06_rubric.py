"""The card's rubric pinned by synthetic predictions whose score is computed by hand."""

import math

import numpy as np
import pytest

from rle_tasks.core.scoring import Outcome
from rle_tasks.f06_pose_estimation.scoring import (
    RUBRICS,
    VARIANT,
    group_score,
    reward,
    speed_deduction,
    wrap_angle,
)


def _truth(n=10, shape=1):
    rng = np.random.default_rng(0)
    return np.column_stack(
        [rng.uniform(-0.1, 0.1, n), rng.uniform(-0.1, 0.1, n), rng.uniform(-3, 3, n), np.full(n, shape)]
    )


def test_exact_predictions_score_one():
    t = _truth()
    g, m = group_score(t.copy(), t)
    assert g == pytest.approx(1.0)
    assert m["shape_accuracy"] == 1.0


def test_worst_five_errors_by_hand():
    t = _truth()
    p = t.copy()
    # translation errors 1..10 mm along x; worst five: 6..10 mm, mean 8 mm
    p[:, 0] += np.arange(1, 11) * 1e-3
    # angle errors 0.01..0.10 rad; worst five 0.06..0.10, mean 0.08 rad
    p[:, 2] = t[:, 2] + np.arange(1, 11) * 0.01
    g, m = group_score(p, t)
    expected = 0.5 * math.exp(-((0.008 / 0.01) ** 2)) + 0.5 * math.exp(-((0.08 / 0.1) ** 2))
    assert g == pytest.approx(expected)  # 0.5 e^-0.64 + 0.5 e^-0.64 = 0.5273
    assert m["worst5_xy_m"] == pytest.approx(0.008)
    assert m["worst5_theta_rad"] == pytest.approx(0.08)


def test_wrapped_angle_pi_minus_vs_minus_pi_plus():
    t = _truth()
    t[:, 2] = math.pi - 0.01
    p = t.copy()
    p[:, 2] = -math.pi + 0.01
    # the wrapped error is 0.02 rad, not 2 pi - 0.02
    assert abs(float(wrap_angle(p[0, 2] - t[0, 2]))) == pytest.approx(0.02)
    g, m = group_score(p, t)
    assert m["worst5_theta_rad"] == pytest.approx(0.02)
    assert g == pytest.approx(0.5 + 0.5 * math.exp(-((0.02 / 0.1) ** 2)))  # 0.98020


def test_one_wrong_shape_zeroes_the_group():
    t = _truth()
    p = t.copy()
    p[3, 3] = 2.0
    g, m = group_score(p, t)
    assert g == 0.0
    assert m["shape_accuracy"] == pytest.approx(0.9)


def test_missing_prediction_is_wrong():
    t = _truth()
    p = t.copy()
    p[0] = np.nan
    g, _ = group_score(p, t)
    assert g == 0.0


@pytest.mark.parametrize(
    ("fps", "d"), [(100.0, 0.0), (10.0, 0.0), (5.5, 0.1), (1.0, 0.2), (0.3, 0.2), (0.0, 0.2)]
)
def test_speed_deduction(fps, d):
    # D = 0.2 clip((10 - nu) / 9, 0, 1): nu = 5.5 -> 0.2 * 4.5 / 9 = 0.1
    assert speed_deduction(fps) == pytest.approx(d)


def test_report_matches_closed_form():
    ga, gb, fps = [0.9, 0.8, 0.7], [0.6, 0.5], 4.0
    ded = speed_deduction(fps)  # 0.2 * 6 / 9
    rubric = RUBRICS["06-pose-b-rgbd"]
    rep = rubric.report(
        {
            "frames": Outcome({VARIANT: float(np.mean(ga))}),
            "trajectories": Outcome({VARIANT: float(np.mean(gb))}),
        },
        valid=True,
        deductions={VARIANT: ded},
    )
    assert rep.score == pytest.approx(0.3 * 0.8 + 0.7 * 0.55 - 0.2 * 6 / 9)
    assert rep.score == pytest.approx(reward(ga, gb, fps))
    # floor at 0
    assert reward([0.0], [0.1], 0.5) == 0.0


def test_gate_cap_scores_zero():
    rep = RUBRICS["06-pose-a-rgb"].report({}, valid=False, caps=("gate",))
    assert rep.score == 0.0 and rep.cap == 0.0
