"""Pocket-cube state reading, turn classification and the solved predicate, on synthetic poses."""

import math

import mujoco
import numpy as np
import pytest

from rle_tasks.f03_physical_reasoning.cube.group import QUATS
from rle_tasks.f03_physical_reasoning.cube.lattice import CUBIES, MOVES, SLOTS, SOLVED, LatticeState
from rle_tasks.f03_physical_reasoning.cube.reading import (
    ALIGNED_TOL,
    LIFT_CLEARANCE,
    STILL_SPEED,
    CubePoses,
    CubeReading,
    check_solved,
    read,
)
from rle_tasks.f03_physical_reasoning.cube.turns import SETTLED_TOL, classify, transitions

HALF = 0.0158
TABLE_Z = 0.4


def _axis_quat(axis, angle):
    q = np.zeros(4)
    mujoco.mju_axisAngle2Quat(q, np.asarray(axis, float), angle)
    return q


def _poses(state: LatticeState, world=None, centre=(0, 0, 0.5), tweak=None, speed=0.0):
    """World poses of a cube in ``state``, rotated as a whole by ``world``; ``tweak`` = (cubie, quat)."""
    world = np.array([1.0, 0, 0, 0]) if world is None else world
    quats, pos = [], []
    for i in range(8):
        q = np.empty(4)
        mujoco.mju_mulQuat(q, world, QUATS[state.orient[i]])
        if tweak is not None and tweak[0] == i:
            mujoco.mju_mulQuat(q, tweak[1], q.copy())
        quats.append(q)
        m = np.empty(9)
        mujoco.mju_quat2Mat(m, q)
        pos.append(np.asarray(centre) + m.reshape(3, 3) @ (SLOTS[i] * 0.016))
    return CubePoses(np.array(quats), np.array(pos), np.full(8, speed), HALF)


def test_reading_recovers_the_state_up_to_whole_cube_rotation():
    rng = np.random.default_rng(3)
    for _ in range(20):
        state = SOLVED.apply_all([MOVES[i] for i in rng.integers(0, 12, 12)])
        world = rng.normal(size=4)
        world /= np.linalg.norm(world)
        r = read(_poses(state, world))
        assert r.state == state.normalized()
        assert r.misalignment < 1e-6


def test_misalignment_is_the_angle_of_the_worst_cubie():
    tweak = (CUBIES.index("UFR"), _axis_quat([0, 0, 1], math.radians(7.0)))
    r = read(_poses(SOLVED, tweak=tweak))
    assert r.state == SOLVED
    assert r.misalignment == pytest.approx(math.radians(7.0), abs=1e-9)


@pytest.mark.parametrize("move", MOVES)
def test_each_quarter_turn_is_classified(move):
    before = SOLVED.apply_all(["R", "F'", "U"])
    got = classify(before, before.apply(move))
    # D, L, B turns read as the same-sense turn of U, R, F (the frame moves with the DBL cubie).
    assert got == {"D": "U", "L": "R", "B": "F"}.get(move[0], move[0]) + move[1:]


def test_half_turns_count_two_and_two_layers_or_twists_are_unclassified():
    s = SOLVED.apply("F")
    assert classify(s, s.apply_all(["U", "U"])) == "U2"
    assert classify(s, s.apply_all(["D'", "D'"])) == "U2"
    t = transitions([_reading(s, 0), _reading(s.apply_all(["R", "R"]), 0)])
    assert [(x.move, x.quarter_turns) for x in t] == [("R2", 2)]
    assert classify(s, s.apply_all(["U", "R"])) is None
    # One corner twisted in place (120 deg about its diagonal): not reachable by turns at all.
    ufr = CUBIES.index("UFR")
    diag = SLOTS[ufr] / math.sqrt(3)
    q = _axis_quat(diag, 2 * math.pi / 3)
    idx = int(np.argmax(np.abs(QUATS @ q)))
    forced = LatticeState(tuple(idx if i == ufr else 0 for i in range(8)))
    assert classify(SOLVED, forced) is None
    with pytest.raises(ValueError, match="same puzzle state"):
        classify(s, s.rotated(5))


def _reading(state, angle_deg):
    return CubeReading(state.normalized(), math.radians(angle_deg))


def test_transitions_count_only_settled_changes():
    s0 = SOLVED
    s1 = s0.apply("U")
    s2 = s1.apply("R'")
    readings = [
        _reading(s0, 1),
        _reading(s0, 30),  # turning
        _reading(s1, 40),  # past halfway, not settled
        _reading(s0, 44),  # wobbles back over halfway: still no turn
        _reading(s1, 20),
        _reading(s1, 2),  # settled: U
        _reading(s1, float("nan")),  # a bad sample is skipped
        _reading(s2, 9),  # settled: R'
        _reading(s2.rotated(7), 0),  # whole-cube rotation: no transition
    ]
    t = transitions(readings)
    assert [x.move for x in t] == ["U", "R'"]
    assert [x.index for x in t] == [5, 7]
    assert math.degrees(SETTLED_TOL) == 10


def test_wobble_around_halfway_without_settling_counts_nothing():
    s0, s1 = SOLVED, SOLVED.apply("F")
    readings = [_reading(s0, 0)] + [_reading(s1 if k % 2 else s0, 44) for k in range(50)] + [_reading(s0, 1)]
    assert transitions(readings) == []


def test_solved_predicate_passes_a_held_solved_cube():
    c = check_solved(_poses(SOLVED, centre=(0, 0, TABLE_Z + 0.1)), TABLE_Z)
    assert c.solved and c.reason == ""


@pytest.mark.parametrize(
    ("poses", "reason"),
    [
        (_poses(SOLVED.apply("U"), centre=(0, 0, TABLE_Z + 0.1)), "faces are not uniform"),
        (
            _poses(SOLVED, centre=(0, 0, TABLE_Z + 0.1), tweak=(0, _axis_quat([0, 0, 1], math.radians(8)))),
            "off the lattice",
        ),
        (_poses(SOLVED, centre=(0, 0, TABLE_Z + 0.1), speed=2 * STILL_SPEED), "moving"),
        (_poses(SOLVED, centre=(0, 0, TABLE_Z + 0.032)), "not held above the table"),
        (_poses(SOLVED, centre=(0, 0, float("nan"))), "not finite"),
    ],
)
def test_solved_predicate_fails_for_the_stated_reason(poses, reason):
    c = check_solved(poses, TABLE_Z)
    assert not c.solved and reason in c.reason


def test_thresholds_are_the_documented_ones():
    assert math.degrees(ALIGNED_TOL) == pytest.approx(5.0)
    assert (STILL_SPEED, LIFT_CLEARANCE) == (0.02, 0.005)


def test_lowest_corner_of_a_cube_resting_on_a_corner():
    # Cube balanced on a corner: the body diagonal is vertical, the lowest corner is sqrt(3)*32 mm below
    # the centre (closed form: half the space diagonal of a 64 mm cube, minus the cubie gaps).
    from rle_tasks.f03_physical_reasoning.cube.reading import lowest_corner

    axis = np.cross([1, 1, 1], [0, 0, 1]) / np.linalg.norm(np.cross([1, 1, 1], [0, 0, 1]))
    world = _axis_quat(axis, math.acos(1 / math.sqrt(3)))
    poses = _poses(SOLVED, world=world, centre=(0, 0, 1.0))
    expect = 1.0 - math.sqrt(3) * (0.016 + HALF)
    assert lowest_corner(poses) == pytest.approx(expect, abs=1e-9)


def test_a_broken_cube_is_not_solved_and_does_not_crash():
    # Two cubies in one slot (physically impossible unless the cube came apart): UFL turned onto UFR.
    broken = LatticeState((0, _onto_ufr(), 0, 0, 0, 0, 0, 0))
    assert not broken.is_valid() and not broken.is_solved()
    with pytest.raises(ValueError, match="broken cube"):
        broken.facelets()
    c = check_solved(_poses(broken, centre=(0, 0, TABLE_Z + 0.1)), TABLE_Z)
    assert not c.solved and "broken" in c.reason
    assert classify(SOLVED, broken) is None


def _onto_ufr() -> int:
    """A rotation taking the UFL cubie's home slot onto UFR's."""
    from rle_tasks.f03_physical_reasoning.cube.group import ROTATIONS

    ufl, ufr = SLOTS[CUBIES.index("UFL")], SLOTS[CUBIES.index("UFR")]
    return next(r for r in range(24) if np.array_equal(ROTATIONS[r] @ ufl, ufr))
