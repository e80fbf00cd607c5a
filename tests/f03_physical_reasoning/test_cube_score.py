"""The pocket cube's reward formula: passing and failing cases, each for its stated reason."""

import pytest

from rle_tasks.f03_physical_reasoning.cube.lattice import SOLVED, LatticeState
from rle_tasks.f03_physical_reasoning.cube.scoring import UNCLASSIFIED_CAP, cube_reward
from rle_tasks.f03_physical_reasoning.cube.turns import Transition, classify

SCRAMBLE = ["R", "U", "F'", "U"]  # optimal 4 (checked below against the table)


def _path(start: LatticeState, moves):
    out, s = [], start
    for k, m in enumerate(moves):
        t = s.apply(m)
        out.append(Transition(k, s.normalized(), t.normalized(), classify(s, t)))
        s = t
    return out


def _solve(extra=()):
    start = SOLVED.apply_all(SCRAMBLE)
    inverse = [m[:-1] if m.endswith("'") else m + "'" for m in reversed(SCRAMBLE)]
    moves = [*extra, *(m[:-1] if m.endswith("'") else m + "'" for m in reversed(extra)), *inverse]
    return _path(start, moves)


def test_optimal_solve_scores_one():
    t = _solve()
    s = cube_reward(solved=True, optimal=4, ledger_turns=4, transitions=t)
    assert (s.reward, s.turns, s.cap) == (1.0, 4, None)


def test_excess_turns_score_opt_over_turns():
    t = _solve(extra=["F", "R"])  # F R R' F' wasted: 8 turns
    s = cube_reward(solved=True, optimal=4, ledger_turns=8, transitions=t)
    assert s.turns == 8 and s.reward == pytest.approx(4 / 8)


def test_unsolved_scores_zero():
    t = _solve()[:-1]
    s = cube_reward(solved=False, optimal=4, ledger_turns=3, transitions=t)
    assert s.reward == 0.0 and s.reason == "cube not solved"


def test_ledger_disagreeing_with_transitions_scores_zero():
    t = _solve()
    s = cube_reward(solved=True, optimal=4, ledger_turns=3, transitions=t)
    assert s.reward == 0.0 and "invalid counters: ledger records 3 turns, transitions show 4" in s.reason


def test_unclassified_transition_caps_at_half():
    start = SOLVED.apply_all(SCRAMBLE)
    t = _path(start, ["U'", "F"])
    s1 = t[-1].after
    # An unclassifiable jump (two layers at once) straight to the rest of the solve.
    jumped = s1.apply_all(["U'", "R'"])
    t.append(Transition(2, s1.normalized(), jumped.normalized(), classify(s1, jumped)))
    assert t[-1].move is None
    s = cube_reward(solved=True, optimal=4, ledger_turns=2, transitions=t)
    assert s.unclassified == 1 and s.cap == UNCLASSIFIED_CAP
    assert s.reward == UNCLASSIFIED_CAP and "capped at 0.5" in s.reason
    # The cap does not lift a lower score: 4 optimal, 10 classified turns -> 0.4.
    t10 = _solve(extra=["F", "R", "U"]) + t[-1:]
    s10 = cube_reward(solved=True, optimal=4, ledger_turns=10, transitions=t10)
    assert s10.reward == pytest.approx(0.4)


def test_scramble_optimum_is_four():
    from rle_tasks.f03_physical_reasoning.cube.distance import optimal_turns

    assert optimal_turns(SOLVED.apply_all(SCRAMBLE)) == 4


def test_a_half_turn_counts_two_quarter_turns():
    from rle_tasks.f03_physical_reasoning.cube.distance import optimal_turns

    start = SOLVED.apply_all(["R", "R", "U"])
    assert optimal_turns(start) == 3
    mid = start.apply("U'")
    t = [
        Transition(0, start.normalized(), mid.normalized(), classify(start, mid)),
        Transition(1, mid.normalized(), SOLVED, classify(mid, SOLVED)),
    ]
    assert [x.move for x in t] == ["U'", "R2"]
    s = cube_reward(solved=True, optimal=3, ledger_turns=3, transitions=t)
    assert (s.turns, s.reward) == (3, 1.0)
    assert cube_reward(solved=True, optimal=3, ledger_turns=2, transitions=t).reward == 0.0


def test_out_of_range_optimum_is_our_bug():
    with pytest.raises(ValueError, match="0..14"):
        cube_reward(solved=True, optimal=15, ledger_turns=0, transitions=[])
