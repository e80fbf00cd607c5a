"""05-robotwin-open / -robust on the bimanual stand-in: episode sets drawn from the secret, the card's
completion thresholds, the instruction, the verifier on recipes that must fail for their named
reasons and one that replays, and the development workspace."""

import hashlib
import importlib.util
import json

import numpy as np
import pytest

from rle_design.ledger.verify import verify_ledger
from rle_tasks.core.registry import get_task
from rle_tasks.core.runtime.devenv import layout_workspace, ledger_key
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret, load_secret
from rle_tasks.core.solutions import materialise
from rle_tasks.core.task import VerifyContext
from rle_tasks.core.verify import VerifierSetupError, run_verify
from rle_tasks.envs.libero.replay import train
from rle_tasks.f05_nanovla import datasets, training, verifier
from rle_tasks.f05_nanovla.scoring import required_complete, rubric

OPEN, ROBUST = verifier.STANDIN_OPEN_ID, verifier.STANDIN_ROBUST_ID
TASK = get_task(OPEN)


@pytest.fixture
def demos(tmp_path, monkeypatch):
    """A three-episode dataset in the stand-in's format (actions only matter to the baselines)."""
    d = tmp_path / "demos"
    d.mkdir()
    files = {}
    for t in range(3):
        name = f"task{t}_seed000.npz"
        a = np.tile(np.r_[np.array([0, -1.571, 1.571, -1.571, -1.571, 0]), 1.0], 2).astype(np.float32)
        np.savez(
            d / name, actions=np.tile(a, (5, 1)), state=np.zeros((6, 16), np.float32), language=np.array("x")
        )
        files[name] = hashlib.sha256((d / name).read_bytes()).hexdigest()
    text = json.dumps({"files": files})
    (d / "manifest.json").write_text(text)
    (d / "manifest.sha256").write_text(hashlib.sha256(text.encode()).hexdigest() + "\n")
    monkeypatch.setenv(datasets.STANDIN_DATASET_ENV, str(d))
    return d


def _ctx(**kw):
    return VerifyContext(secret=Secret(PUBLIC_KEY, public=True), **kw)


def _other():
    return VerifyContext(secret=Secret(b"another key", public=False))


@pytest.mark.parametrize(("task_id", "n", "need"), [(OPEN, 300, 285), (ROBUST, 225, 214)])
def test_the_sets_are_the_cards_sizes_of_held_out_layouts_drawn_from_the_secret(task_id, n, need):
    full = verifier.episode_set(task_id, _ctx())
    assert len(full) == n and len(set(full)) == n and required_complete(n) == need
    suite = "standin" if task_id == OPEN else "standin_robust"
    assert {s for s, _, _ in full} == {suite}
    assert [sum(t == k for _, t, _ in full) for k in range(3)] == [n // 3] * 3
    lo, hi = verifier.STANDIN_SEEDS
    assert all(lo <= seed < hi for _, _, seed in full)  # never a demonstration or development seed
    assert full == verifier.episode_set(task_id, _ctx()) != verifier.episode_set(task_id, _other())
    order = verifier.episode_order(task_id, _ctx())
    assert sorted(order) == sorted(full) and {t for _, t, _ in order[:3]} == {0, 1, 2}


def test_instruction_and_rubric_agree():
    for task_id, n, need in ((OPEN, 300, 285), (ROBUST, 225, 214)):
        table = rubric(task_id, n).markdown_table()
        text = get_task(task_id).instruction
        assert table in text and f"fewer than {need} of the {n} episodes" in table
        assert "stand-in" in text and "16," in text and "14 values" in text
    assert "distractor" in get_task(ROBUST).instruction and "distractor" not in TASK.instruction


def test_an_oversized_recipe_is_refused_before_anything_runs():
    report, internal = run_verify(TASK, materialise(TASK, "baseline/too_large"), _ctx(quick=True))
    assert not internal and report.score == 0.0 and report.cap == 0.0 and not report.valid
    assert [e.code for e in report.errors] == ["f05.solution_too_large"]
    assert report.native_metrics["episodes_requested"] == verifier.STANDIN_QUICK_EPISODES


def test_a_missing_dataset_is_the_operators_fault(tmp_path, monkeypatch):
    monkeypatch.setenv(datasets.STANDIN_DATASET_ENV, str(tmp_path / "nothing"))
    with pytest.raises(VerifierSetupError, match="make standin-demos"):
        run_verify(TASK, materialise(TASK, "baseline/mean_action"), _ctx(quick=True))


def test_the_mean_action_recipe_replays_every_episode_and_succeeds_in_none(demos):
    report = verifier.verify(
        materialise(TASK, "baseline/mean_action"), _ctx(episodes=3), task_id=OPEN, max_steps=6
    )
    nm = report.native_metrics
    assert report.valid and report.errors == () and report.cap is None
    assert nm["complete"] == 3 and nm["successes"] == 0 and report.score == 0.0 and nm["partial"]
    assert [(e["suite"], e["task"], e["init_index"]) for e in nm["episodes"]] == sorted(
        verifier.episode_order(OPEN, _ctx())[:3], key=lambda e: e[1]
    )
    assert all(e["steps"] == 6 and e["requests"] == 1 for e in nm["episodes"])  # one 8-action chunk


def test_a_nan_server_completes_no_episode(demos):
    report = verifier.verify(
        materialise(TASK, "baseline/nan_server"), _ctx(episodes=1), task_id=OPEN, max_steps=6
    )
    codes = [e.code for e in report.errors]
    assert "protocol.non_finite" in codes and "f05.incomplete" in codes
    assert report.score == 0.0 and report.cap == 0.0 and report.native_metrics["complete"] == 0


def test_the_robust_track_replays_in_perturbed_scenes(demos):
    robust = get_task(ROBUST)
    report = verifier.verify(
        materialise(robust, "baseline/mean_action"), _ctx(episodes=1), task_id=ROBUST, max_steps=4
    )
    (ep,) = report.native_metrics["episodes"]
    assert report.task_id == ROBUST and report.errors == () and ep["suite"] == "standin_robust"
    assert (ep["suite"], ep["task"], ep["init_index"]) == verifier.episode_order(ROBUST, _ctx())[0]


def _client(ws):
    spec = importlib.util.spec_from_file_location("standin_client", ws / "standin_client.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_the_workspace_meters_served_episodes_of_clean_scenes(tmp_path, demos):
    root = tmp_path / "ws"
    ws = layout_workspace(TASK, root, serve=True, ledger_dir=tmp_path / "ledger")
    try:
        assert (root / "demos").resolve() == demos.resolve() and not (root / "libero_client.py").exists()
        text = (root / "standin_client.py").read_text()
        assert "layout seed 0-999999" in text and "20,000 episodes" in text
        sub = root / "submission"
        (sub / "solution.py").write_bytes(
            (materialise(TASK, "baseline/mean_action") / "solution.py").read_bytes()
        )
        assert train(sub / "solution.py", demos, sub) is None
        with _client(root).connect() as dev:
            with pytest.raises(RuntimeError, match="ledger.bad_request"):
                dev.evaluate("submission", [(3, 0)])  # the stand-in has tasks 0-2
            with pytest.raises(RuntimeError, match="ledger.bad_request"):
                dev.evaluate(
                    "submission", [(0, verifier.STANDIN_SEEDS[0])]
                )  # evaluation seeds are not for development
            (res,) = dev.evaluate("submission", [(1, 42)], max_steps=3)
            assert res["init_index"] == 42 and res["steps"] == 3 and not res["success"] and res["fault"] == ""
            assert dev.info() == {
                "episodes_used": 1,
                "episodes_left": 19_999,
                "episodes_this_session": 1,
                "budget": 20_000,
            }
            dev.seal()
        ws.server.wait(30)
    finally:
        ws.close()
    verdict = verify_ledger(ws.ledger_path, ledger_key(load_secret(), TASK.id), TASK.id)
    assert verdict.valid and verdict.steps == 1, verdict


def test_the_reference_recipe_trains_and_serves_in_the_sandbox(tmp_path, monkeypatch, short_reference):
    """The shipped reference on a one-episode dataset of real views, its training cut to 20 steps (the
    full recipe trains for minutes): training writes a checkpoint in the sandbox, serving answers
    every request with 14-D actions, and the episode completes."""
    from rle_tasks.envs.standin import StandinEnv
    from rle_tasks.envs.standin.demos import record

    d = tmp_path / "demos"
    d.mkdir()
    ok, rec = record(StandinEnv(0), 0)
    assert ok
    np.savez(d / "task0_seed000.npz", language=np.array("lift the pot with both arms"), **rec)
    text = json.dumps(
        {"files": {"task0_seed000.npz": hashlib.sha256((d / "task0_seed000.npz").read_bytes()).hexdigest()}}
    )
    (d / "manifest.json").write_text(text)
    (d / "manifest.sha256").write_text(hashlib.sha256(text.encode()).hexdigest() + "\n")
    monkeypatch.setenv(datasets.STANDIN_DATASET_ENV, str(d))
    sub = short_reference(TASK)
    report = verifier.verify(sub, _ctx(episodes=1), task_id=OPEN, max_steps=10)
    nm = report.native_metrics
    assert report.valid and report.errors == () and report.cap is None, report.errors
    (ep,) = nm["episodes"]
    assert ep["fault"] == "" and ep["steps"] == 10 and ep["requests"] == 2  # chunks of 5 executed actions
    assert nm["ckpt_bytes"] > 100_000 and nm["train_s"] < 120


def test_the_same_recipe_and_secret_give_the_same_report(demos):
    """Determinism of the stand-in verifier (the training wall time is the one measured field)."""
    texts = []
    for _ in range(2):
        report = verifier.verify(
            materialise(TASK, "baseline/mean_action"), _ctx(episodes=2), task_id=OPEN, max_steps=5
        )
        d = report.to_dict()
        d.pop("elapsed_s", None)
        d["native_metrics"].pop("train_s")
        texts.append(json.dumps(d))
    assert texts[0] == texts[1]


def _recipe(path):
    spec = importlib.util.spec_from_file_location("standin_recipe", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_the_robust_reference_is_the_recipe_with_image_augmentation(tmp_path):
    from rle_tasks.f05_nanovla.solutions import ROBUST_AUGMENT, with_augmentation

    clean = (materialise(TASK, "reference") / "solution.py").read_text()
    robust = (materialise(get_task(ROBUST), "reference") / "solution.py").read_text()
    assert "\nAUGMENT = 0\n" in clean and ROBUST_AUGMENT > 0
    assert robust == clean.replace("\nAUGMENT = 0\n", f"\nAUGMENT = {ROBUST_AUGMENT}\n")
    (tmp_path / "solution.py").write_text("AUGMENT = 1\n")
    with pytest.raises(ValueError, match="no longer declares AUGMENT = 0"):
        with_augmentation(tmp_path)


def test_augmented_frames_are_seeded_and_recolour_the_table():
    """On a synthetic view (a tan table, a blue block): the table's colour is found, a copy keeps the
    frames' shape and type, the same seed gives the same copy, and the table takes new colours while
    its pixels stay one colour (the boxes and the block aside)."""
    recipe = _recipe(materialise(TASK, "reference") / "solution.py")
    frames = np.empty((4, 128, 128, 3), np.uint8)
    frames[:] = (220, 188, 148)
    frames[:, 50:70, 50:70] = (40, 60, 200)
    table = recipe.table_colour(frames)
    assert np.abs(table - (220, 188, 148)).max() <= 4
    a = recipe.augment(frames, table, np.random.default_rng(3))
    b = recipe.augment(frames, table, np.random.default_rng(3))
    assert a.shape == frames.shape and a.dtype == np.uint8
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, recipe.augment(frames, table, np.random.default_rng(4)))
    for copy in a:
        colours, counts = np.unique(copy.reshape(-1, 3), axis=0, return_counts=True)
        commonest = colours[counts.argmax()]
        assert np.abs(commonest.astype(int) - (220, 188, 148)).max() > 10  # a new table colour
        assert counts.max() > 0.6 * 128 * 128  # the table: one colour, boxes and block aside


def test_a_cached_training_is_reused_only_when_asked_and_a_retraining_is_compared(
    demos, tmp_path, monkeypatch
):
    from rle_tasks.core.solutions import CACHE_ENV

    monkeypatch.setenv(CACHE_ENV, str(tmp_path / "cache"))
    sub = materialise(TASK, "baseline/mean_action")
    first = verifier.verify(sub, _ctx(episodes=1), task_id=OPEN, max_steps=6).native_metrics
    assert first["training"] == "trained" and "ckpt_reproduced" not in first
    entry = training.cache_entry((sub / "solution.py").read_bytes(), first["dataset_sha256"])
    assert (entry / "ckpt.pt").is_file() and entry.is_relative_to(tmp_path / "cache")
    reused = verifier.verify(sub, _ctx(episodes=1, reuse_training=True), task_id=OPEN, max_steps=6)
    assert reused.native_metrics["training"] == "reused"
    assert reused.native_metrics["ckpt_sha256"] == first["ckpt_sha256"] and reused.score == 0.0
    again = verifier.verify(sub, _ctx(episodes=1), task_id=OPEN, max_steps=6).native_metrics
    assert again["training"] == "trained" and again["ckpt_reproduced"] is True
    # another recipe (or other data) has another entry; a damaged entry is not used
    assert training.cache_entry(b"other", first["dataset_sha256"]) != entry
    (entry / "ckpt.pt").write_bytes(b"damaged")
    assert (
        verifier.verify(sub, _ctx(episodes=1, reuse_training=True), task_id=OPEN, max_steps=6).native_metrics[
            "training"
        ]
        == "trained"
    )


def test_a_shipped_checkpoint_is_used_only_when_its_pins_match(demos, tmp_path, monkeypatch):
    """A shipped checkpoint stands in for a training when its recipe, dataset, torch and limit pins
    match and its own sha256 does; with the cache empty, a changed recipe or a damaged file trains."""
    import hashlib
    import json
    from importlib.metadata import version

    from rle_tasks.core.solutions import CACHE_ENV

    monkeypatch.setenv(CACHE_ENV, str(tmp_path / "cache"))
    sub = materialise(TASK, "baseline/mean_action")
    recipe = (sub / "solution.py").read_bytes()
    first = verifier.verify(sub, _ctx(episodes=1), task_id=OPEN, max_steps=6).native_metrics
    ckpt = (training.cache_entry(recipe, first["dataset_sha256"]) / "ckpt.pt").read_bytes()
    ship = tmp_path / "shipped"
    ship.mkdir()
    (ship / "x.pt").write_bytes(ckpt)
    pins = {
        "solution_sha256": hashlib.sha256(recipe).hexdigest(),
        "dataset_sha256": first["dataset_sha256"],
        "torch": version("torch"),
        "train_limit_s": training.train_limit(),
        "ckpt_sha256": hashlib.sha256(ckpt).hexdigest(),
        "meta_sha256": None,
        "train_s": 1.0,
    }
    (ship / "manifest.json").write_text(json.dumps({"x": pins}))
    monkeypatch.setattr(training, "SHIPPED", ship)
    monkeypatch.setenv(CACHE_ENV, str(tmp_path / "empty-cache"))
    got = verifier.verify(
        sub, _ctx(episodes=1, reuse_training=True), task_id=OPEN, max_steps=6
    ).native_metrics
    assert got["training"] == "shipped" and got["ckpt_sha256"] == first["ckpt_sha256"]
    assert training.shipped(recipe + b"\n", first["dataset_sha256"]) is None  # another recipe
    assert training.shipped(recipe, "0" * 64) is None  # other data
    (ship / "x.pt").write_bytes(ckpt + b"x")  # damaged: not used
    assert training.shipped(recipe, first["dataset_sha256"]) is None
