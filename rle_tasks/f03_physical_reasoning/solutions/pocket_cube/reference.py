"""Reference solve of ``03-pocket-cube`` for a public scramble: top-layer turns and whole-cube pitches.

The right hand has two moves (``top_turns``): a quarter turn of the top layer (``U`` or ``U'`` in the
world frame) and a pitch of the whole cube (-90 degrees about world y). The program knows the public
scramble (its quarter turns, published) and tracks the cube's state in the world frame through its own
moves; it reads no cube pose. A Dijkstra search over world-frame states finds the plan with the fewest
quarter turns and, among those, the fewest pitches. Pitches bring the +x face on top, so the faces U,
R, D, L can be turned: every state of the ``<U, R>`` subgroup is reachable, and the public scrambles
``R U R' U'`` and ``U R U R'`` are solved in their optimal 4 quarter turns. Finally the hand lifts the
cube off its stand and holds it still. The left arm stays at home (this reference uses no hand-off).
"""

from __future__ import annotations

import heapq
from typing import Any

import numpy as np

from rle_design.control import CartesianHelper

from ...cube.env import ARM_ACTION
from ...cube.group import index_of
from ...cube.lattice import SOLVED, LatticeState
from .top_turns import hold_up, pitch, quarter_turn

PITCH = index_of(np.array([[0, 0, -1], [0, 1, 0], [1, 0, 0]]))
"""Rotation index of the pitch: -90 degrees about world y."""
TURN_SENSE = {"U": -1.0, "U'": 1.0}
"""Wrist sense of each world-frame top turn (``U`` is clockwise seen from above)."""


def plan(scramble: str, max_turns: int = 8) -> list[str]:
    """Fewest-turn, then fewest-pitch sequence of ``"U"``, ``"U'"``, ``"P"`` solving ``scramble``.

    Raises:
        ValueError: No plan within ``max_turns`` quarter turns (the scramble leaves ``<U, R>``).
    """
    start = SOLVED.apply_all(scramble.split()).normalized()
    queue: list[tuple[int, int, tuple[int, ...], tuple[str, ...]]] = [(0, 0, start.orient, ())]
    seen: set[tuple[int, ...]] = set()
    while queue:
        cost, _, orient, moves = heapq.heappop(queue)
        state = LatticeState(orient)
        if state.is_solved():
            return list(moves)
        if orient in seen or cost // 100 > max_turns:
            continue
        seen.add(orient)
        nexts = [("P", state.rotated(PITCH), 1), ("U", state.apply("U"), 100), ("U'", state.apply("U'"), 100)]
        for move, nxt, c in nexts:
            if nxt.orient not in seen:
                heapq.heappush(queue, (cost + c, len(queue) + len(seen), nxt.orient, (*moves, move)))
    raise ValueError(f"no plan within {max_turns} quarter turns for {scramble!r}")


def solve(env: Any, scramble: str) -> list[str]:
    """Execute the plan for the public ``scramble`` (its quarter turns) through metered actions."""
    moves = plan(scramble)
    obs = env.reset()
    right = CartesianHelper(env.step, obs, arm=1, n_arms=2, arm_size=ARM_ACTION)
    home_quat = np.asarray(obs["arms"][1]["ee_quat"], dtype=float)
    for move in moves:
        if move == "P":
            pitch(right, home_quat)
        else:
            quarter_turn(right, home_quat, TURN_SENSE[move])
    right.wait(10)
    hold_up(right, home_quat)
    return moves
