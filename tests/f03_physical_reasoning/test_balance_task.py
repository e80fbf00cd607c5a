"""03-balance-coins: weighings counted by the environment, the ledger gate, the mat check, the score."""

from pathlib import Path

import mujoco
import numpy as np
import pytest

from rle_design.control.layout import MODE, zero_action
from rle_design.ledger import MeteredSession
from rle_tasks.core.runtime.devenv import ledger_key
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.core.task import VerifyContext
from rle_tasks.f03_physical_reasoning.balance import env as be
from rle_tasks.f03_physical_reasoning.balance import scene as bs
from rle_tasks.f03_physical_reasoning.balance import verifier as bv
from rle_tasks.f03_physical_reasoning.constants import BALANCE_ID, STEP_BUDGET, WALL_TIME_S

PUBLIC = Secret(PUBLIC_KEY, public=True)
INSTANCE = bv.instance(PUBLIC)


@pytest.fixture(scope="module")
def env():
    return be.make_env(INSTANCE, image_size=None)


def _put(model, data, cube: int, pos) -> None:
    adr = model.jnt_qposadr[model.joint(f"{bs.cube_name(cube)}_free").id]
    data.qpos[adr : adr + 7] = [*pos, 1.0, 0.0, 0.0, 0.0]
    data.qvel[model.jnt_dofadr[model.joint(f"{bs.cube_name(cube)}_free").id] :][:6] = 0.0
    mujoco.mj_forward(model, data)


def _on_pan(model, data, pan: int, dx: float = 0.0) -> np.ndarray:
    return be.balance_observation(model, data)["pans"][pan] + np.array([dx, 0.0, 0.016])


@pytest.mark.parametrize(
    ("heavy_only", "w", "score"),
    [(True, 0, 1.0), (True, 2, 1.0), (True, 3, 2 / 3), (True, 5, 0.4), (False, 2, 0.0)],
)
def test_score_is_the_cards(heavy_only, w, score):
    # 0 unless only the heavy cube is on the mat; then 1 for w <= 2, else 2/w.
    assert bv.weighing_score(heavy_only, w) == pytest.approx(score)


def test_instance_comes_from_the_secret():
    a, b = bv.instance(Secret(b"one", False)), bv.instance(Secret(b"one", False))
    assert a == b and 0 <= a.heavy < 9 and 0.008 <= a.heavy_extra <= 0.012
    heavies = {bv.instance(Secret(bytes([k]) * 8, False)).heavy for k in range(40)}
    assert len(heavies) >= 6  # spread over the cubes


def test_a_weighing_is_a_release_run_with_cubes_on_the_pans(env):
    model = env.build()
    env.prepare(model)
    data = mujoco.MjData(model)
    env.reset(model, data)
    hold, release = zero_action(), zero_action()
    release[MODE] = 1.0
    for _ in range(3):  # released with empty pans: not a weighing
        env.step(model, data, release)
    env.step(model, data, hold)
    assert data.userdata[be.WEIGHINGS] == 0
    _put(model, data, 0, _on_pan(model, data, 0))
    _put(model, data, 1, _on_pan(model, data, 1))
    assert be.cubes_on_pans(model, data) == [[0], [1]]
    for _ in range(20):  # one run counts once
        env.step(model, data, release)
    assert data.userdata[be.WEIGHINGS] == 1
    assert be.balance_observation(model, data)["released"] is True
    env.step(model, data, hold)
    angle = bs.beam_angle(model, data)
    for _ in range(5):  # locked where it stood
        env.step(model, data, hold)
    assert bs.beam_angle(model, data) == pytest.approx(angle, abs=2e-3)
    env.step(model, data, release)
    assert data.userdata[be.WEIGHINGS] == 2
    env.reset(model, data)  # a reset restores the scene, not the count
    assert data.userdata[be.WEIGHINGS] == 2
    assert bs.beam_angle(model, data) == pytest.approx(0.0, abs=1e-9)
    assert be.cubes_on_pans(model, data) == [[], []]
    assert be.balance_observation(model, data)["weighings"] == 2


def _replayed_state(env, placements: dict[int, tuple[float, float, float]]):
    model = env.build()
    env.prepare(model)
    data = mujoco.MjData(model)
    env.reset(model, data)
    for cube, pos in placements.items():
        _put(model, data, cube, pos)
    return model, data


def test_mat_check_after_robot_free_settling(env):
    mx, my = be.MAT_CENTRE
    rest = be.TABLE.top_z + 0.015
    cases = {
        "heavy alone": ({INSTANCE.heavy: (mx, my, rest)}, (INSTANCE.heavy,)),
        "heavy dropped from 5 cm": ({INSTANCE.heavy: (mx + 0.02, my, rest + 0.05)}, (INSTANCE.heavy,)),
        "heavy and a light one": (
            {INSTANCE.heavy: (mx - 0.02, my, rest), (INSTANCE.heavy + 1) % 9: (mx + 0.025, my, rest)},
            tuple(sorted((INSTANCE.heavy, (INSTANCE.heavy + 1) % 9))),
        ),
        "off the mat": ({INSTANCE.heavy: (mx + be.MAT_HALF + 0.01, my, rest)}, ()),
    }
    for name, (placements, expected) in cases.items():
        model, data = _replayed_state(env, placements)
        assert bv.settle_final(INSTANCE, model, data).on_mat == expected, name


def _session_ledger(env, tmp: Path, n_actions: int = 4, secret: Secret = PUBLIC) -> Path:
    sub = tmp / "submission"
    sub.mkdir()
    session = MeteredSession(
        env,
        task_id=BALANCE_ID,
        budget=STEP_BUDGET,  # the card's limits: the gate refuses a session served with others
        key=ledger_key(secret, BALANCE_ID),
        ledger_path=sub / "ledger.jsonl",
        wall_time_s=WALL_TIME_S,
    )
    session.reset()
    for _ in range(n_actions):
        session.step(zero_action())
    session.seal()
    return sub


def test_a_short_honest_session_is_valid_and_scores_zero(env, tmp_path):
    report = bv.verify(_session_ledger(env, tmp_path), VerifyContext(secret=PUBLIC))
    assert report.valid and report.score == 0.0
    assert report.checkpoints[0].message == "no cube rests on the mat"
    assert report.native_metrics["weighings"] == 0 and report.native_metrics["actions"] == 4


def _tamper_drop_record(lines):
    return lines[:2] + lines[3:]


def _tamper_edit_final_state(lines):
    return lines[:-2] + [lines[-2].replace('"time":', '"time":1')] + lines[-1:]


@pytest.mark.parametrize(
    ("name", "tamper", "code"),
    [
        ("record removed", _tamper_drop_record, "ledger.truncated"),
        ("final record edited", _tamper_edit_final_state, "ledger.altered"),
        ("unsealed", lambda lines: lines[:-1], "ledger.unsealed"),
        ("missing", None, "ledger.missing"),
    ],
)
def test_tampered_ledgers_score_zero_with_the_reason(env, tmp_path, name, tamper, code):
    sub = _session_ledger(env, tmp_path, n_actions=40)
    path = sub / "ledger.jsonl"
    if tamper is None:
        path.unlink()
    else:
        path.write_text("\n".join(tamper(path.read_text().splitlines())) + "\n")
    report = bv.verify(sub, VerifyContext(secret=PUBLIC))
    assert report.score == 0.0 and not report.valid, name
    assert report.errors[0].code == code, (name, report.errors)
    assert report.native_metrics["ledger"] == code


def test_a_ledger_of_another_secret_is_refused(env, tmp_path):
    sub = _session_ledger(env, tmp_path, secret=Secret(b"agent-forged", public=False))
    report = bv.verify(sub, VerifyContext(secret=PUBLIC))
    assert report.score == 0.0 and report.errors[0].code == "ledger.forged_key"


def test_verification_is_deterministic(env, tmp_path):
    sub = _session_ledger(env, tmp_path)
    a = bv.verify(sub, VerifyContext(secret=PUBLIC))
    b = bv.verify(sub, VerifyContext(secret=PUBLIC))
    assert (a.score, a.checkpoints, a.native_metrics) == (b.score, b.checkpoints, b.native_metrics)
