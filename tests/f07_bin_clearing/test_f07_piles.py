"""Seeded piles: drawn within the card's ranges, reproducible, and never tunnelling out of the bin."""

import numpy as np
import pytest

from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.core.task import VerifyContext
from rle_tasks.f07_bin_clearing.public.pile import PileSpec, part_qpos_adr, settle_pile
from rle_tasks.f07_bin_clearing.public.workcell import (
    BIN_CENTER,
    BIN_FLOOR_TOP,
    BIN_INNER,
    BRACKET_FRICTION,
    build_workcell,
)
from rle_tasks.f07_bin_clearing.verifier import hidden_piles


def test_hidden_piles_follow_the_secret_and_the_card():
    ctx = VerifyContext(secret=Secret(PUBLIC_KEY, public=True))
    piles = hidden_piles(ctx)
    assert len(piles) == 8 and piles == hidden_piles(ctx)
    assert all(12 <= p.n_parts <= 16 and 0.7 <= p.friction_scale <= 1.3 for p in piles)
    other = hidden_piles(VerifyContext(secret=Secret(b"another key", public=False)))
    assert other != piles


@pytest.mark.physics
def test_settled_piles_stay_in_the_bin(full_battery):
    n = 200 if full_battery else 8
    models = {}
    for seed in range(1000, 1000 + n):
        pile = PileSpec.public(seed)
        if pile.n_parts not in models:
            models[pile.n_parts] = build_workcell(pile.n_parts).compile()
        model = models[pile.n_parts]
        parts = [g for g in range(model.ngeom) if model.geom(g).name.startswith("bracket")]
        model.geom_friction[parts, 0] = BRACKET_FRICTION * pile.friction_scale
        data = settle_pile(model, pile)
        pos = np.array([data.qpos[a : a + 3] for a in part_qpos_adr(model, pile.n_parts)])
        inside = np.all(np.abs(pos[:, :2] - BIN_CENTER) < np.array(BIN_INNER) / 2, axis=1)
        inside &= (pos[:, 2] > BIN_FLOOR_TOP - 0.002) & (pos[:, 2] < BIN_FLOOR_TOP + 0.15)
        assert inside.all(), f"seed {seed}: parts {np.flatnonzero(~inside)} outside the bin"
        assert np.isfinite(data.qpos).all()
