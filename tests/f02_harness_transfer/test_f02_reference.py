"""The shipped reference harness (``solutions/reference/kitchen``) through one transfer unit: the scripted
fresh agent, in the sandbox, calls its entry point on group 1's held-out task (``StowFruitInDrawer``) in
the first public-key kitchen; the replayed ledger must score as measured (1.0: the lemon in the drawer,
the drawer closed; about 25 s)."""

from __future__ import annotations

from pathlib import Path

import pytest

from rle_tasks.core.secrets import PUBLIC_KEY, Secret
from rle_tasks.f02_harness_transfer.groups import GROUPS
from rle_tasks.f02_harness_transfer.task import targets
from rle_tasks.f02_harness_transfer.transfer import TransferUnit, run_unit

pytestmark = pytest.mark.physics


@pytest.fixture(scope="module")
def harness(tmp_path_factory) -> Path:
    """The reference harness as shipped (materialised: its shared modules generated into it)."""
    from rle_tasks.core.solutions import build
    from rle_tasks.f02_harness_transfer.solutions import _set

    dest = tmp_path_factory.mktemp("ref") / "solution"
    build(_set("02-group-01", {"reference": ("", 0.0)}, "kitchen"), "reference", dest)
    return dest / "agent_harness"


MEASURED = 1.0
"""s_trial of this unit when the reference was written."""
MARGIN = 0.5
"""Allowed drop (one of the two conjuncts)."""


def test_reference_harness_solves_the_first_public_kitchen_of_group_1(harness):
    group = next(g for g in GROUPS if g.number == 1)
    layout, episode = targets(Secret(PUBLIC_KEY, public=True), group)[0]
    unit = TransferUnit(0, group.held_out, layout, episode, harness, b"r" * 32, "ref/agent-0")
    result = run_unit(unit)
    assert result.status == "scored" and result.agent == "ran", result.message[-800:]
    assert result.n == 2 and result.b == 0
    assert result.score >= MEASURED - MARGIN, (result.b, result.m, result.n, result.message[-800:])
