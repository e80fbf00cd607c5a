"""The kitchen's ``segment`` query (L2): SAM3's schema, the fridge handle, determinism, noise bounds."""

from __future__ import annotations

import numpy as np
import pytest

from rle_design.ledger import LedgerError
from rle_tasks.envs.kitchen.env import KitchenEnv
from rle_tasks.envs.kitchen.scene import ROBOT
from rle_tasks.envs.kitchen.segmentation import SEGMENT_NOISE, noisy_mask, shift_or, words
from rle_tasks.envs.kitchen.sessions import KitchenScenes

LARGE_PX = 500
"""Instances of at least this many pixels count as large (IoU > 0.5 after the noise)."""


@pytest.fixture(scope="module")
def kitchen():
    """An L2 OpenFridge session in pretrain kitchen 0 (the robot beside the closed fridge)."""
    session = KitchenScenes("OpenFridge", level=2, evaluation=None).open_session(task_id="test", budget=None)
    obs = session.reset({"kitchen": 0, "seed": 0})
    return session, obs


def band(mask: np.ndarray, steps: int) -> tuple[np.ndarray, np.ndarray]:
    """(mask eroded ``steps`` times, mask dilated ``steps`` times) by one pixel (4-neighbourhood)."""
    inner, outer = mask, mask
    for _ in range(steps):
        inner, outer = ~shift_or(~inner), shift_or(outer)
    return inner, outer


def test_schema(kitchen) -> None:
    session, obs = kitchen
    h, w = obs["depth"][ROBOT.cameras[0]].shape
    for camera in ROBOT.cameras:
        out = session.query("segment", {"prompt": "door", "camera": camera})
        n = len(out["scores"])
        assert out["masks"].shape == (n, h, w) and out["masks"].dtype == bool
        assert out["boxes"].shape == (n, 4) and out["boxes"].dtype == np.float64
        assert out["scores"].shape == (n,) and out["scores"].dtype == np.float64
        lo, hi = SEGMENT_NOISE["score"]
        assert np.all((out["scores"] >= lo) & (out["scores"] <= hi))
        for mask, box in zip(out["masks"], out["boxes"]):
            rows, cols = np.nonzero(mask)
            assert box.tolist() == [cols.min(), rows.min(), cols.max(), rows.max()]  # x0 y0 x1 y1, inclusive
    none = session.query("segment", {"prompt": "unicorn", "camera": ROBOT.cameras[0]})
    assert none["masks"].shape == (0, h, w) and none["boxes"].shape == (0, 4) and none["scores"].shape == (0,)


def test_handle_found_on_the_fridge_handle(kitchen) -> None:
    # "handle" and "fridge handle" are independent draws of the noise (a large instance is missed with
    # probability SEGMENT_NOISE["miss"] = 0.03 per query): in each view that shows the handle one of
    # them finds it, "handle" in all views but at most one, and "fridge handle" finds no other handle.
    session, _ = kitchen
    env, model, data = session.env, session.model, session.data
    seen = hits = 0
    for camera in ROBOT.cameras:
        pix, names, _ = env.instances(model, data, camera)
        exact = pix == names.index("fridge_handle")
        if exact.sum() < SEGMENT_NOISE["small_px"]:
            continue
        seen += 1
        found = []
        for prompt in ("handle", "fridge handle"):
            masks = session.query("segment", {"prompt": prompt, "camera": camera})["masks"]
            found.append(any((m & exact).sum() > 0.5 * exact.sum() for m in masks))
            if prompt == "fridge handle":
                assert len(masks) <= 1
        assert any(found), camera
        hits += found[0]
    assert seen >= 2 and hits >= seen - 1  # the spawn faces the fridge: the handle is in view


def test_deterministic(kitchen) -> None:
    session, _ = kitchen
    for camera in ROBOT.cameras:
        a = session.query("segment", {"prompt": "handle", "camera": camera})
        for prompt in ("handle", " Handles "):  # the same words: the same draw
            b = session.query("segment", {"prompt": prompt, "camera": camera})
            for key in ("masks", "boxes", "scores"):
                assert np.array_equal(a[key], b[key])


def test_noisy_mask_bounds_and_thin_instances() -> None:
    # A 12 x 12 square and a one-pixel line: misses at about the documented rates (binomial, 400
    # draws: 0.03 +- 0.03, 0.3 +- 0.08), every answer between the mask eroded and dilated twice, and
    # the line (which one erosion would erase) never answered empty.
    square = np.zeros((32, 32), bool)
    square[10:22, 10:22] = True
    line = np.zeros((32, 32), bool)
    line[16, 4:24] = True  # 20 px < small_px
    for mask, rate, tol in ((square, SEGMENT_NOISE["miss"], 0.03), (line, SEGMENT_NOISE["miss_small"], 0.08)):
        inner, outer = band(mask, 2)
        missed = 0
        for seed in range(400):
            out = noisy_mask(mask, np.random.default_rng(seed))
            if out is None:
                missed += 1
                continue
            assert out.any() and np.all(out <= outer) and np.all(inner <= out)
            assert (out & mask).sum() / (out | mask).sum() > (0.5 if mask is square else 0.15)
        assert abs(missed / 400 - rate) < tol


def test_noise_within_documented_bounds(kitchen) -> None:
    # One-pixel erosion or dilation, then flips on the one-pixel band of the new boundary: every mask
    # lies between the exact mask eroded and dilated twice; large instances keep IoU > 0.5.
    session, _ = kitchen
    env, model, data = session.env, session.model, session.data
    checked = large = 0
    for camera in ROBOT.cameras:
        pix, names, labels = env.instances(model, data, camera)
        for label in sorted(set(labels[i] for i in np.unique(pix[pix >= 0]))):
            same = [i for i, lab in enumerate(labels) if set(words(label)) <= set(words(lab))]
            out = session.query("segment", {"prompt": label, "camera": camera})
            for mask in out["masks"]:
                i = max(same, key=lambda k: (mask & (pix == k)).sum() / (mask | (pix == k)).sum())
                exact = pix == i
                inner, outer = band(exact, 2)
                assert np.all(mask <= outer) and np.all(inner <= mask), (camera, names[i])
                checked += 1
                if exact.sum() >= LARGE_PX:
                    large += 1
                    assert (mask & exact).sum() / (mask | exact).sum() > 0.5, (camera, names[i])
    assert checked >= 20 and large >= 8


def test_level_1_refuses(kitchen) -> None:
    session, _ = kitchen
    env = session.env
    l1 = KitchenEnv(xml=env.xml, scene=env.scene, level=1, image_size=env.image_size)
    with pytest.raises(LedgerError) as err:
        l1.query(session.model, session.data, "segment", {"prompt": "handle"})
    assert err.value.code == "ledger.bad_request"
    for args in ({"prompt": ""}, {"prompt": "handle", "camera": "nowhere"}):
        with pytest.raises(LedgerError) as err:
            session.query("segment", args)
        assert err.value.code == "ledger.bad_request"
