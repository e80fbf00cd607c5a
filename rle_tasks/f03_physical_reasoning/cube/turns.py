"""Turn classification: the sequence of settled lattice states and the quarter turn between each two.

The verifier samples the cube at every control step and reads its nearest lattice state relative to the
DBL cubie (``reading.read``). A reading is *settled* when every cubie is within ``SETTLED_TOL`` of the
lattice; only settled readings enter the sequence, so a layer wobbling around its halfway point never
produces a turn, and a turn is counted once the layer has settled into its new quarter-turn position.

Each change between consecutive settled states is classified: it is the quarter turn ``X`` when
``after == before.apply(X)`` for one of the six generators that keep DBL in place (U, U', R, R', F, F';
a turn of the D, L or B layer reads as the same-sense turn of the opposite face, because the cube's frame
moves with DBL), or the half turn ``X2`` (two quarter turns of one layer, e.g. spun past its 90-degree
position between two settled readings). Anything else (two layers at once, a forced twist, a broken
cube) is unclassified.

``SETTLED_TOL`` = 10 deg: above the mechanism's settled misalignment (2 deg, tested) with margin for
the grip's squeeze, and far inside the 45-degree basin of a lattice state, so a settled reading is never
ambiguous.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

from rle_tasks.f03_physical_reasoning.cube.coords import GENERATORS
from rle_tasks.f03_physical_reasoning.cube.lattice import LatticeState
from rle_tasks.f03_physical_reasoning.cube.reading import CubeReading

SETTLED_TOL = math.radians(10.0)


@dataclass(frozen=True)
class Transition:
    """A change between two consecutive settled states.

    Attributes:
        index: Sample index (e.g. control step) of the reading that settled into ``after``.
        before: Normalised state before.
        after: Normalised state after.
        move: The quarter turn (one of ``coords.GENERATORS``), a half turn (``"U2"``, ``"R2"``,
            ``"F2"``), or None when unclassified.
    """

    index: int
    before: LatticeState
    after: LatticeState
    move: str | None

    @property
    def classified(self) -> bool:
        """True when the change is one quarter turn or one half turn of a single layer."""
        return self.move is not None

    @property
    def quarter_turns(self) -> int:
        """Quarter turns in the transition: 1, 2 for a half turn, 0 when unclassified."""
        if self.move is None:
            return 0
        return 2 if self.move.endswith("2") else 1


def classify(before: LatticeState, after: LatticeState) -> str | None:
    """The quarter turn (or half turn ``X2``) taking ``before`` to ``after`` (up to a whole-cube
    rotation), or None.

    Raises:
        ValueError: The two states are the same puzzle state (no transition to classify).
    """
    b, a = before.normalized(), after.normalized()
    if a == b:
        raise ValueError("no transition: the two states are the same puzzle state")
    for move in GENERATORS:
        if b.apply(move).normalized() == a:
            return move
    for move in GENERATORS[::2]:
        if b.apply(move).apply(move).normalized() == a:
            return move + "2"
    return None


def transitions(readings: Iterable[CubeReading]) -> list[Transition]:
    """Classified transitions between the settled states of a sequence of readings.

    Args:
        readings: One reading per sample, in time order; the first settled one is the start state.
    """
    out: list[Transition] = []
    current: LatticeState | None = None
    for index, reading in enumerate(readings):
        if not reading.misalignment <= SETTLED_TOL:  # also rejects NaN
            continue
        state = reading.state.normalized()
        if current is None:
            current = state
        elif state != current:
            out.append(Transition(index, current, state, classify(current, state)))
            current = state
    return out
