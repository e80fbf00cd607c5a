"""03-pocket-cube: quarter turns executed by the right wrist through metered 14-D actions, recounted by
the verifier from the replay (``solutions/pocket_cube/top_turns``)."""

from __future__ import annotations

import os

import pytest

import rle_tasks.f03_physical_reasoning.cube.verifier as cube_verifier
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.core.task import VerifyContext
from rle_tasks.f03_physical_reasoning.cube.scene import PUBLIC_SCRAMBLES, CubeInstance, instance
from rle_tasks.f03_physical_reasoning.solutions.pocket_cube import record

PUBLIC = Secret(PUBLIC_KEY, public=True)
CTX = VerifyContext(secret=PUBLIC, quick=True)


@pytest.mark.physics
@pytest.mark.skipif(os.environ.get("RLE_FULL_BATTERY") != "1", reason="15 s; the reference covers it")
def test_a_u_turn_on_the_public_scramble_is_classified_and_the_counters_agree(tmp_path):
    """``R U R' U'`` then one clockwise top turn (``U``): 3 quarter turns from solved, not solved, score 0;
    the session counted the turn the verifier recounts."""
    root = record("top_turns", PUBLIC, tmp_path / "u", senses=(-1.0,))
    report = cube_verifier.verify(root, CTX)
    measured = report.checkpoints[0].measured
    assert report.valid and report.score == 0.0
    assert report.checkpoints[0].message.startswith("cube not solved (faces are not uniform")
    assert measured["moves"] == ["U"] and measured["session_turns"] == measured["turns"] == 1
    assert instance(PUBLIC) == CubeInstance.from_moves(PUBLIC_SCRAMBLES[0])
    assert CubeInstance(instance(PUBLIC).state.apply("U").normalized()).optimal == 3
    assert measured["lowest_corner_above_stand_top"] > 0.005  # held: only the faces fail


@pytest.mark.physics
def test_excess_turns_lower_the_reward_to_opt_over_turns(tmp_path, monkeypatch):
    """Shallow test scramble ``U``: U' U U' by the wrist (3 quarter turns, optimum 1) solves it; reward 1/3."""
    inst = CubeInstance.from_moves("U")
    root = record("top_turns", PUBLIC, tmp_path / "u3", inst=inst, senses=(1.0, -1.0, 1.0))
    monkeypatch.setattr(cube_verifier, "instance", lambda secret: inst)
    report = cube_verifier.verify(root, CTX)
    measured = report.checkpoints[0].measured
    assert measured["moves"] == ["U'", "U", "U'"] and measured["session_turns"] == 3
    assert measured["solved"] and report.score == pytest.approx(1 / 3)
