"""The pocket cube's move model: cubies, faces, quarter turns and states on the lattice.

Frame (the core's): +x is R, -x L, +y B, -y F, +z U, -z D. Cubie ``i`` starts in slot ``SLOTS[i]`` (a
sign vector, one per octant) and carries three stickers, coloured by the faces its home slot touches.
A lattice state gives, for each cubie, its orientation relative to the core as one of the 24 cube
rotations; the cubie's slot follows from it (``g @ SLOTS[i]``) because each cubie turns about the
core's centre on a ball joint.

A quarter turn ``X`` turns the layer of face ``X`` by 90 degrees clockwise seen from outside that face
(right-hand rotation by -90 degrees about the face's outward normal); ``X'`` is its inverse. Two states
that differ by a rotation of the whole cube are the same puzzle state: ``normalized`` maps both to the
representative whose DBL cubie is at home.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rle_tasks.f03_physical_reasoning.cube.group import IDENTITY, INV, MUL, ROTATIONS, quarter_turn

FACES = ("U", "R", "F", "D", "L", "B")
"""Face names in facelet order."""
FACE_NORMALS: dict[str, np.ndarray] = {
    "U": np.array([0, 0, 1]),
    "R": np.array([1, 0, 0]),
    "F": np.array([0, -1, 0]),
    "D": np.array([0, 0, -1]),
    "L": np.array([-1, 0, 0]),
    "B": np.array([0, 1, 0]),
}
"""Outward unit normal of each face in the core frame."""
COLOURS: dict[str, tuple[float, float, float, float]] = {
    "U": (0.95, 0.95, 0.95, 1.0),
    "R": (0.80, 0.05, 0.05, 1.0),
    "F": (0.05, 0.60, 0.15, 1.0),
    "D": (0.95, 0.85, 0.05, 1.0),
    "L": (0.95, 0.45, 0.05, 1.0),
    "B": (0.05, 0.20, 0.80, 1.0),
}
"""Sticker colour (RGBA) of each face of the solved cube: white, red, green, yellow, orange, blue."""


def _slot_name(p: np.ndarray) -> str:
    return ("U" if p[2] > 0 else "D") + ("B" if p[1] > 0 else "F") + ("R" if p[0] > 0 else "L")


SLOTS: np.ndarray = np.array(
    [[1, -1, 1], [-1, -1, 1], [-1, 1, 1], [1, 1, 1], [1, -1, -1], [-1, -1, -1], [-1, 1, -1], [1, 1, -1]],
    dtype=np.int64,
)
"""``(8, 3)`` home slot (octant sign vector) of each cubie."""
CUBIES: tuple[str, ...] = tuple(_slot_name(p) for p in SLOTS)
"""Cubie names by home slot: UFR, UFL, UBL, UBR, DFR, DFL, DBL, DBR."""
ANCHOR = CUBIES.index("DBL")
"""The cubie held fixed by ``normalized`` (so only U, R and F turns are needed to reach every state)."""

MOVES: tuple[str, ...] = tuple(f + s for f in FACES for s in ("", "'"))
"""The 12 quarter turns: U, U', R, R', F, F', D, D', L, L', B, B'."""
MOVE_ROTATION: dict[str, int] = {
    f + s: quarter_turn(FACE_NORMALS[f], -1 if s == "" else 1) for f in FACES for s in ("", "'")
}
"""Rotation index of each quarter turn, applied to the cubies of the turned layer."""


def inverse_move(move: str) -> str:
    """``"U"`` -> ``"U'"`` and back."""
    return move[:-1] if move.endswith("'") else move + "'"


@dataclass(frozen=True)
class LatticeState:
    """Orientation of each cubie relative to the core, on the lattice.

    Attributes:
        orient: Eight rotation indices (``group.ROTATIONS``), one per cubie in ``CUBIES`` order.
    """

    orient: tuple[int, ...]

    def __post_init__(self) -> None:
        if len(self.orient) != 8 or any(not 0 <= int(o) < 24 for o in self.orient):
            raise ValueError(f"a lattice state has 8 rotation indices in 0..23, got {self.orient}")

    def slots(self) -> np.ndarray:
        """``(8, 3)`` current slot of each cubie."""
        return np.einsum("nij,nj->ni", ROTATIONS[list(self.orient)], SLOTS)

    def apply(self, move: str) -> LatticeState:
        """State after one quarter turn ``move`` (one of ``MOVES``)."""
        if move not in MOVE_ROTATION:
            raise ValueError(f"unknown move '{move}'; moves are {', '.join(MOVES)}")
        q = MOVE_ROTATION[move]
        in_layer = self.slots() @ FACE_NORMALS[move[0]] > 0
        return LatticeState(tuple(int(MUL[q, o]) if m else int(o) for o, m in zip(self.orient, in_layer)))

    def apply_all(self, moves: list[str] | tuple[str, ...]) -> LatticeState:
        """State after a sequence of quarter turns."""
        state = self
        for move in moves:
            state = state.apply(move)
        return state

    def rotated(self, rot: int) -> LatticeState:
        """The same puzzle state with the whole cube rotated by ``ROTATIONS[rot]`` (core frame)."""
        return LatticeState(tuple(int(MUL[rot, o]) for o in self.orient))

    def normalized(self) -> LatticeState:
        """Whole-cube rotation of this state that brings the DBL cubie home (a canonical form)."""
        return self.rotated(int(INV[self.orient[ANCHOR]]))

    def same_puzzle(self, other: LatticeState) -> bool:
        """True when the two states differ only by a rotation of the whole cube."""
        return self.normalized() == other.normalized()

    def is_valid(self) -> bool:
        """True when the eight cubies occupy eight different slots (a cube that is not broken)."""
        return len({tuple(p) for p in self.slots()}) == 8

    def facelets(self) -> str:
        """24 sticker colours as face letters: faces in ``FACES`` order, four stickers per face.

        Within a face the stickers are listed by the slot they occupy, in ``SLOTS`` order.

        Raises:
            ValueError: Two cubies occupy the same slot (``is_valid`` is False).
        """
        if not self.is_valid():
            raise ValueError(f"broken cube: two cubies in one slot ({self.slots().tolist()})")
        rots = ROTATIONS[list(self.orient)]
        slots = self.slots()
        out = []
        for face in FACES:
            n = FACE_NORMALS[face]
            for slot in SLOTS[SLOTS @ n > 0]:
                i = int(np.flatnonzero((slots == slot).all(axis=1))[0])
                home_normal = rots[i].T @ n  # the cubie's sticker that now faces n, in its home frame
                out.append(_face_of(home_normal))
        return "".join(out)

    def is_solved(self) -> bool:
        """Every face shows a single colour (the solved state up to a rotation of the whole cube)."""
        if not self.is_valid():
            return False
        f = self.facelets()
        return all(len(set(f[4 * k : 4 * k + 4])) == 1 for k in range(6))


def _face_of(normal: np.ndarray) -> str:
    for face, n in FACE_NORMALS.items():
        if np.array_equal(n, normal):
            return face
    raise ValueError(f"not a face normal: {normal}")


SOLVED = LatticeState((IDENTITY,) * 8)
"""The solved cube in its home orientation."""
