"""Verifiers of the family's tasks, by task id (each task subpackage holds its own ``verifier.verify``;
``verify`` dispatches by ``task_id``).

Every tabletop verifier follows the same protocol: the ledger gate (``session.open_ledger``: a
missing, unsealed, altered or non-replaying ledger scores 0 with its reason), the replay of the
sealed session (``session.replay_ledger``), then the task's measurement (for the free pieces of the
tower and the cantilever, after the robot-free settle of the final scene, ``scene.settle``).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from rle_tasks.core.report import VerifierReport
from rle_tasks.core.task import VerifyContext

from .balance import verifier as balance
from .cantilever import verifier as cantilever
from .constants import BALANCE_ID, CANTILEVER_ID, CUBE_ID, HIDDEN_COM_ID, TOWER_ID
from .cube import verifier as cube
from .hidden_com import verifier as hidden_com
from .tower import verifier as tower

VERIFIERS: dict[str, Callable[[Path, VerifyContext], VerifierReport]] = {
    TOWER_ID: tower.verify,
    CANTILEVER_ID: cantilever.verify,
    BALANCE_ID: balance.verify,
    CUBE_ID: cube.verify,
    HIDDEN_COM_ID: hidden_com.verify,
}


def verify(root: Path, ctx: VerifyContext, *, task_id: str) -> VerifierReport:
    """Score the sealed session at ``root`` for ``task_id`` with that task's verifier."""
    return VERIFIERS[task_id](root, ctx)
