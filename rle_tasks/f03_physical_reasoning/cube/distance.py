"""Optimal quarter-turn distance of every pocket-cube state: a breadth-first table, cached with a checksum.

The table holds, for each of the 3,674,160 coordinates of ``coords``, the fewest quarter turns that
solve the state (int8). It is built breadth-first from the solved state over the six DBL-fixing
generators with numpy (a few seconds), written once under the user cache directory
(``rle_tasks.core.solutions.cache_root() / "cube"``), and checked against a pinned SHA-256 every time it
is loaded: a missing, truncated or altered file is rebuilt. Nothing is written into the repository.
"""

from __future__ import annotations

import functools
import hashlib
import os
import tempfile
from pathlib import Path

import numpy as np

from rle_design.errors import RleError
from rle_tasks.core.solutions import cache_root
from rle_tasks.f03_physical_reasoning.cube.coords import N_STATES, N_TWIST, encode, move_tables
from rle_tasks.f03_physical_reasoning.cube.lattice import LatticeState

TABLE_SHA256 = "4b3bbc767618c65f79eb3488e57cab414fab3e73ee481aeb723ac92832ec9112"
"""SHA-256 of the full table's bytes (int8, coordinate order); a mismatch means a corrupt cache."""
TABLE_FILE = "qtm_distance_v1.npy"
UNREACHED = -1


def build_table(max_depth: int | None = None) -> np.ndarray:
    """Breadth-first quarter-turn distances from the solved state.

    Args:
        max_depth: Stop after this depth (states farther away stay ``UNREACHED``); None: the full table.

    Returns:
        ``(N_STATES,)`` int8 distances, ``UNREACHED`` (-1) where not reached.
    """
    perm_move, twist_move = move_tables()
    perm_move = perm_move.astype(np.int64) * N_TWIST
    dist = np.full(N_STATES, UNREACHED, dtype=np.int8)
    dist[0] = 0  # coordinate 0 is the solved state
    frontier = np.zeros(1, dtype=np.int64)
    depth = 0
    while frontier.size and (max_depth is None or depth < max_depth):
        nxt = (perm_move[frontier // N_TWIST] + twist_move[frontier % N_TWIST]).ravel()
        nxt = nxt[dist[nxt] == UNREACHED]
        depth += 1
        dist[nxt] = depth
        frontier = np.flatnonzero(dist == depth)
    return dist


def depth_counts(table: np.ndarray) -> list[int]:
    """Number of states at each distance 0, 1, ... (unreached states not counted)."""
    return np.bincount(table[table >= 0].astype(np.int64)).tolist()


def table_path() -> Path:
    """Where the cached table lives (outside the repository)."""
    return cache_root() / "cube" / TABLE_FILE


def _digest(table: np.ndarray) -> str:
    return hashlib.sha256(np.ascontiguousarray(table, dtype=np.int8).tobytes()).hexdigest()


def _load(path: Path) -> np.ndarray | None:
    try:
        table = np.load(path, allow_pickle=False)
    except (OSError, ValueError, EOFError):
        return None
    if table.dtype != np.int8 or table.shape != (N_STATES,) or _digest(table) != TABLE_SHA256:
        return None
    return table


def _store(table: np.ndarray, path: Path) -> None:
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
        with os.fdopen(fd, "wb") as fh:
            np.save(fh, table, allow_pickle=False)
        os.replace(tmp, path)
    except OSError:
        pass  # an unwritable cache only costs a rebuild next time


@functools.cache
def distance_table() -> np.ndarray:
    """The full distance table: loaded from the cache when intact, else rebuilt and cached.

    Raises:
        RleError: A rebuilt table does not match the pinned checksum (a bug in the move model).
    """
    path = table_path()
    table = _load(path)
    if table is None:
        table = build_table()
        digest = _digest(table)
        if digest != TABLE_SHA256:
            raise RleError(
                f"rebuilt pocket-cube distance table has sha256 {digest}, expected {TABLE_SHA256}",
                code="cube.table_checksum",
            )
        _store(table, path)
    table.setflags(write=False)
    return table


def optimal_turns(state: LatticeState) -> int:
    """Fewest quarter turns that solve ``state`` (any whole-cube orientation counts as solved)."""
    return int(distance_table()[encode(state)])
