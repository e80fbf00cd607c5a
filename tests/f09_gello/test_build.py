"""The reference build's placement rules (``solutions/build.py``, ``solutions/attached.py``), pinned
on closed forms: the passive hold's loss estimate and a counterweight split into a pair."""

import numpy as np
import pytest

from rle_tasks.f09_gello.public.gello_helpers import load_leader, residual, workspace_grid
from rle_tasks.f09_gello.solutions.attached import SERVO_FRICTION, hold_failure
from rle_tasks.f09_gello.solutions.build import apply_design, exact_design


def test_hold_failure_is_the_fraction_of_a_turn_where_the_moment_beats_the_friction():
    f = SERVO_FRICTION
    assert hold_failure(0.5 * f) == 0.0 and hold_failure(f) == 0.0
    # |sin| > 1/2 on 2/3 of a turn (asin(1/2) = pi/6)
    assert hold_failure(2 * f) == pytest.approx(2 / 3)
    assert hold_failure(f / np.sin(np.pi / 3)) == pytest.approx(1 / 3)  # |sin| > sqrt(3)/2: 1/3
    theta = np.random.default_rng(0).uniform(0, 2 * np.pi, 200_000)
    for moment in (1.2 * f, 1.9 * f, 5 * f):
        assert hold_failure(moment) == pytest.approx(np.mean(moment * np.abs(np.sin(theta)) > f), abs=0.005)


def _worst_residual(path) -> np.ndarray:
    m, km, springs = load_leader(path)
    return np.abs(residual(km, springs, workspace_grid(m.jnt_range, 256))).max(axis=0)


def test_a_pair_astride_the_axis_balances_what_a_single_weight_does(tmp_path):
    single = exact_design("xarm7", {6: (0.08, None)})
    pair = exact_design("xarm7", {6: (0.08, None, 0.055)})
    (one,) = [c for c in single.counterweights if c[0] == "link6"]
    two = [c for c in pair.counterweights if c[0] == "link6"]
    assert len(two) == 2 and two[0][2] == pytest.approx(one[2] / 2) and two[1][2] == pytest.approx(one[2] / 2)
    for (_, pos, _), dz in zip(two, (0.055, -0.055), strict=True):
        assert np.allclose(np.subtract(pos, one[1]), [0.0, 0.0, dz])
    # joint 6's weight puts the wrist's centre of mass where axes 5 and 6 cross: joint 5 needs none
    assert not any(c[0] == "link5" for c in pair.counterweights)
    assert max(pair.unbalanced.values()) < 1e-9
    worst = _worst_residual(apply_design("xarm7", pair, tmp_path / "pair"))
    assert worst.max() < 1e-6  # exact balance at every joint (zero-length spring on joint 2)
    # the same weight at a fixed axial shift leaves joint 5 its moment, more than the servo friction
    shifted = exact_design("xarm7", {6: (0.08, 0.055), 5: None})
    assert shifted.unbalanced[5] > SERVO_FRICTION
    assert _worst_residual(apply_design("xarm7", shifted, tmp_path / "shifted"))[4] > SERVO_FRICTION
