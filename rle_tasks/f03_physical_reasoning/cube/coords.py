"""Integer coordinates of pocket-cube states and their quarter-turn move tables.

With the DBL cubie fixed (``LatticeState.normalized``), a state is the permutation of the other seven
cubies over seven slots (7! = 5040) and their twists (3^7, of which 3^6 = 729 are reachable because the
twists sum to 0 mod 3): 5040 * 729 = 3,674,160 states, indexed ``perm * 729 + twist``. Only U, R and F
turns move the seven cubies with DBL in place, so six generators (U, U', R, R', F, F') span the group.

Twist of a cubie in slot ``p``: 0 when its U/D sticker faces the U/D axis, else the number of
right-hand 120-degree rotations about the slot's diagonal ``p`` that bring it there from the U/D axis
(the standard corner twist, whose sum is invariant under every quarter turn).
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from rle_tasks.f03_physical_reasoning.cube.group import ROTATIONS
from rle_tasks.f03_physical_reasoning.cube.lattice import ANCHOR, SLOTS, LatticeState

N_PERM = math.factorial(7)
N_TWIST = 3**6
N_STATES = N_PERM * N_TWIST
"""3,674,160 states of the pocket cube."""
GENERATORS = ("U", "U'", "R", "R'", "F", "F'")
"""Quarter turns that keep the DBL cubie in place; the columns of the move tables."""

_FREE = [i for i in range(8) if i != ANCHOR]
"""Slots (and cubies) other than DBL, in ``SLOTS`` order; positions 0..6 of the coordinates."""
_SLOT_POS = {tuple(SLOTS[i]): k for k, i in enumerate(_FREE)}


def _twist(slot: np.ndarray, ud_normal: np.ndarray) -> int:
    axis = int(np.argmax(np.abs(ud_normal)))
    if axis == 2:
        return 0
    right_handed = int(np.prod(slot)) > 0  # about (1,1,1) the cycle is x->y->z; mirrored slots reverse it
    return (1 if axis == 0 else 2) if right_handed else (2 if axis == 0 else 1)


def encode(state: LatticeState) -> int:
    """Coordinate index ``0 .. N_STATES - 1`` of a state (after normalising the whole-cube rotation)."""
    norm = state.normalized()
    rots = ROTATIONS[list(norm.orient)]
    slots = norm.slots()
    perm = [0] * 7
    twist = [0] * 7
    for k, i in enumerate(_FREE):
        pos = _SLOT_POS[tuple(slots[i])]
        perm[pos] = k
        ud = rots[i] @ np.array([0, 0, SLOTS[i][2]])
        twist[pos] = _twist(slots[i], ud)
    return perm_rank(perm) * N_TWIST + twist_rank(twist)


def decode(index: int) -> LatticeState:
    """The normalised state (DBL at home) with coordinate ``index``."""
    if not 0 <= index < N_STATES:
        raise ValueError(f"state index {index} outside 0..{N_STATES - 1}")
    perm = perm_unrank(index // N_TWIST)
    twist = twist_unrank(index % N_TWIST)
    orient = [0] * 8
    for pos, k in enumerate(perm):
        cubie = _FREE[k]
        slot = SLOTS[_FREE[pos]]
        orient[cubie] = _orientation_for(cubie, slot, twist[pos])
    return LatticeState(tuple(orient))


def _orientation_for(cubie: int, slot: np.ndarray, twist: int) -> int:
    for r, m in enumerate(ROTATIONS):
        if (
            np.array_equal(m @ SLOTS[cubie], slot)
            and _twist(slot, m @ np.array([0, 0, SLOTS[cubie][2]])) == twist
        ):
            return r
    raise AssertionError("every slot and twist has exactly one orientation")


def perm_rank(perm: list[int]) -> int:
    """Lehmer rank of a permutation of ``0..6``."""
    rank = 0
    items = list(range(7))
    for p in perm:
        i = items.index(p)
        rank = rank * len(items) + i
        items.pop(i)
    return rank


def perm_unrank(rank: int) -> list[int]:
    """Inverse of ``perm_rank``."""
    digits = []
    for base in range(1, 8):
        digits.append(rank % base)
        rank //= base
    items = list(range(7))
    return [items.pop(d) for d in reversed(digits)]


def twist_rank(twist: list[int]) -> int:
    """Rank of seven twists by the first six (base 3); the seventh is implied by the zero sum."""
    rank = 0
    for t in twist[:6]:
        rank = rank * 3 + t
    return rank


def twist_unrank(rank: int) -> list[int]:
    """Inverse of ``twist_rank``: seven twists summing to 0 mod 3."""
    out = []
    for _ in range(6):
        out.append(rank % 3)
        rank //= 3
    out.reverse()
    return [*out, (-sum(out)) % 3]


def _slot_effect(move: str) -> tuple[list[int], list[int]]:
    """Where each of the 7 slot positions goes under ``move``, and the twist it adds there."""
    dest, add = [], []
    for i in _FREE:
        # Probe with a cubie sitting in slot i at twist 0 (orientation from the identity state).
        state = LatticeState(tuple(0 for _ in range(8)))
        moved = state.apply(move)
        new_slot = moved.slots()[i]
        dest.append(_SLOT_POS[tuple(new_slot)])
        rot = ROTATIONS[moved.orient[i]]
        add.append(_twist(new_slot, rot @ np.array([0, 0, SLOTS[i][2]])))
    return dest, add


def move_tables() -> tuple[np.ndarray, np.ndarray]:
    """``(perm_move, twist_move)``: ``(N_PERM, 6)`` and ``(N_TWIST, 6)`` int32 tables over ``GENERATORS``."""
    effects = [_slot_effect(m) for m in GENERATORS]
    perms = list(itertools.permutations(range(7)))
    perm_move = np.empty((N_PERM, len(GENERATORS)), dtype=np.int32)
    for perm in perms:
        r = perm_rank(list(perm))
        for g, (dest, _) in enumerate(effects):
            new = [0] * 7
            for pos, k in enumerate(perm):
                new[dest[pos]] = k
            perm_move[r, g] = perm_rank(new)
    twist_move = np.empty((N_TWIST, len(GENERATORS)), dtype=np.int32)
    for r in range(N_TWIST):
        tw = twist_unrank(r)
        for g, (dest, add) in enumerate(effects):
            new = [0] * 7
            for pos, t in enumerate(tw):
                new[dest[pos]] = (t + add[pos]) % 3
            twist_move[r, g] = twist_rank(new)
    return perm_move, twist_move
