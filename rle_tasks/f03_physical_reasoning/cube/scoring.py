"""Rubric of ``03-pocket-cube`` and its reward, a pure function of the solve, the ledger's turn count and
the transitions.

    reward = 0                              if the ledger's turn count != the quarter turns of the
                                            classified transitions (invalid counters), or unsolved
           = min(1, opt / turns)            otherwise (turns = quarter turns, a half turn counting 2;
                                            1 if turns = opt = 0)
           then capped at 0.5               if any transition is unclassified

``opt`` is the optimal quarter-turn count of the scramble (``distance.optimal_turns``), so a solve in
exactly the optimal number of turns scores 1 and every excess turn lowers the reward as ``opt/turns``
(the card: "excess quarter turns reduce reward relative to the optimum"). ``turns < opt`` can only come
from unclassified transitions doing part of the work; the ``min`` and the cap keep that below 0.5.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from rle_tasks.core.scoring import Cap
from rle_tasks.f03_physical_reasoning.constants import CUBE_ID
from rle_tasks.f03_physical_reasoning.cube.turns import Transition
from rle_tasks.f03_physical_reasoning.rubric import ledger_rubric

UNCLASSIFIED_CAP = 0.5

RUBRIC = ledger_rubric(
    CUBE_ID,
    "attempt",
    "solve",
    "solved cube held still above the table at the end of the one attempt; turns = quarter turns "
    "recounted from the replay (a half turn counts 2), opt = the scramble's optimal quarter turns",
    "0 unless solved with valid counters and no reset; then min(1, opt/turns)",
    caps=(
        Cap(
            "unclassified",
            UNCLASSIFIED_CAP,
            "a change between settled cube states is not one quarter or half turn of a single layer",
        ),
    ),
)
RUBRICS = {CUBE_ID: RUBRIC}


@dataclass(frozen=True)
class CubeScore:
    """The reward and why.

    Attributes:
        reward: In [0, 1].
        reason: Which rule decided it.
        turns: Quarter turns of the classified transitions (a half turn counts 2).
        unclassified: Unclassified transitions.
        optimal: Optimal quarter turns for the scramble.
        cap: The cap applied, or None.
    """

    reward: float
    reason: str
    turns: int
    unclassified: int
    optimal: int
    cap: float | None


def cube_reward(
    *, solved: bool, optimal: int, ledger_turns: int, transitions: Sequence[Transition]
) -> CubeScore:
    """Score an attempt.

    Args:
        solved: The solved predicate at the end of the attempt (``reading.check_solved``).
        optimal: Optimal quarter-turn count of the scramble (0..14).
        ledger_turns: The turn count the metered session recorded in its ledger.
        transitions: The transitions classified from the recorded cube states (``turns.transitions``).
    """
    if not 0 <= optimal <= 14:
        raise ValueError(f"optimal quarter-turn count must be in 0..14 (God's number), got {optimal}")
    turns = sum(t.quarter_turns for t in transitions)
    unclassified = sum(1 for t in transitions if not t.classified)
    cap = UNCLASSIFIED_CAP if unclassified else None

    def done(reward: float, reason: str) -> CubeScore:
        if cap is not None and reward > cap:
            reward, reason = cap, reason + f"; capped at {cap} for {unclassified} unclassified transition(s)"
        return CubeScore(reward, reason, turns, unclassified, optimal, cap)

    if ledger_turns != turns:
        return done(0.0, f"invalid counters: ledger records {ledger_turns} turns, transitions show {turns}")
    if not solved:
        return done(0.0, "cube not solved")
    if turns == 0:
        return done(1.0 if optimal == 0 else 0.0, "solved without a classified turn")
    reward = min(1.0, optimal / turns)
    return done(reward, f"solved in {turns} quarter turns, optimum {optimal}")
