"""03-hidden-com: the answer protocol, the published top-camera geometry, the ledger gate and the score."""

from pathlib import Path

import mujoco
import numpy as np
import pytest

from rle_design.control.layout import MODE, zero_action
from rle_design.ledger import MeteredSession
from rle_tasks.core.runtime.devenv import ledger_key
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.core.task import VerifyContext
from rle_tasks.f03_physical_reasoning import constants as hc
from rle_tasks.f03_physical_reasoning.hidden_com import env as he
from rle_tasks.f03_physical_reasoning.hidden_com import verifier as hv
from rle_tasks.f03_physical_reasoning.hidden_com.scene import QUADRANTS

PUBLIC = Secret(PUBLIC_KEY, public=True)
INSTANCE = hv.instance(PUBLIC)


@pytest.fixture(scope="module")
def env():
    return he.make_env(INSTANCE, image_size=None)


def test_answer_actions_round_trip_and_malformed_ones_decode_to_none():
    for box in range(3):
        for quad in QUADRANTS:
            assert he.decode_answer(he.answer_action(box, quad)) == (box, quad)
    bad = he.answer_action(1, "B")
    bad[10] = 0.0  # between B (-0.25) and C (0.25)
    assert he.decode_answer(bad) is None


def test_first_answer_is_final_and_survives_a_reset(env):
    model = env.build()
    env.prepare(model)
    data = mujoco.MjData(model)
    env.reset(model, data)
    env.step(model, data, he.answer_action(2, "C"))
    env.step(model, data, he.answer_action(2, "A"))  # ignored: box 2 is answered
    malformed = zero_action()
    malformed[MODE] = 1.0
    malformed[7] = 0.5  # no box
    env.step(model, data, malformed)
    env.reset(model, data)
    assert he.recorded_answers(data) == (None, None, "C")
    assert he.answers_observation(model, data) == {"given": [False, False, True], "invalid": 2, "late": 0}


def test_instance_comes_from_the_secret():
    a = hv.instance(Secret(b"x", False))
    assert a == hv.instance(Secret(b"x", False))
    draws = [hv.instance(Secret(bytes([k]) * 8, False)) for k in range(30)]
    assert {q for d in draws for q in d.quadrants} == set(QUADRANTS)
    assert {y for d in draws for y in d.yaws} == {0, 1, 2, 3}


def _project_top(p: np.ndarray, size: tuple[int, int]) -> tuple[int, int]:
    """Pixel (row, col) of world point ``p`` in the top view as the instruction publishes it:
    camera at (0.30, 0, 1.80) looking down, image up = +x, vertical fov 50 deg (pinhole)."""
    h, w = size
    f = (h / 2) / np.tan(np.radians(25.0))
    depth = 1.80 - p[2]
    return int(round(h / 2 - f * (p[0] - 0.30) / depth)), int(round(w / 2 - f * (p[1] - 0.0) / depth))


@pytest.mark.physics
def test_corner_patches_show_where_the_instruction_says():
    from rle_design.control.cameras import render_rgb

    inst = he.HiddenComInstance(("A", "B", "C"), (0, 1, 3))
    e = he.make_env(inst)
    model = e.build()
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.keyframe("initial").id)
    mujoco.mj_forward(model, data)
    img = render_rgb(model, data, ("top",), he.IMAGE_SIZE)["top"].astype(float)
    colour = {"A": 0, "B": 1, "C": 2}  # dominant channel of the red, green and blue patches
    for i, (x, y) in enumerate(he.BOX_XY):
        yaw = inst.yaws[i] * np.pi / 2
        for quad, (sx, sy) in (("A", (1, 1)), ("B", (-1, 1)), ("C", (-1, -1))):
            local = np.array([sx, sy]) * 0.023
            world = np.array([[np.cos(yaw), -np.sin(yaw)], [np.sin(yaw), np.cos(yaw)]]) @ local
            r, c = _project_top(np.array([x + world[0], y + world[1], he.TABLE.top_z + 0.08]), he.IMAGE_SIZE)
            px = img[r - 1 : r + 2, c - 1 : c + 2].reshape(-1, 3).mean(axis=0)
            assert int(np.argmax(px)) == colour[quad], (i, quad, px)


def _session(
    env, tmp: Path, actions, secret: Secret = PUBLIC, wall_time_s: float | None = hc.HIDDEN_COM_WALL_TIME_S
) -> Path:
    sub = tmp / "submission"
    sub.mkdir(parents=True)
    s = MeteredSession(
        env,
        task_id=hc.HIDDEN_COM_ID,
        budget=hc.HIDDEN_COM_STEPS,
        key=ledger_key(secret, hc.HIDDEN_COM_ID),
        ledger_path=sub / "ledger.jsonl",
        wall_time_s=wall_time_s,
    )
    s.reset()
    for a in actions:
        s.step(a)
    s.seal()
    return sub


def _wrong(q: str) -> str:
    return QUADRANTS[(QUADRANTS.index(q) + 1) % 4]


@pytest.mark.parametrize("n_right", [0, 1, 2, 3])
def test_score_is_the_fraction_of_right_answers(env, tmp_path, n_right):
    answers = [q if i < n_right else _wrong(q) for i, q in enumerate(INSTANCE.quadrants)]
    sub = _session(env, tmp_path, [he.answer_action(i, a) for i, a in enumerate(answers)])
    report = hv.verify(sub, VerifyContext(secret=PUBLIC))
    assert report.valid and report.score == pytest.approx(n_right / 3)
    assert report.checkpoints[0].message == f"{n_right} of 3 answers correct (3 given)"


def test_changing_an_answer_is_ignored_and_unanswered_boxes_are_wrong(env, tmp_path):
    q = INSTANCE.quadrants
    actions = [he.answer_action(0, _wrong(q[0])), he.answer_action(0, q[0]), he.answer_action(1, q[1])]
    report = hv.verify(_session(env, tmp_path, actions), VerifyContext(secret=PUBLIC))
    assert report.score == pytest.approx(1 / 3)
    assert report.checkpoints[0].measured == {
        "correct": 1,
        "answered": 2,
        "ignored_answer_actions": 1,
        "late_answer_actions": 0,
    }


@pytest.mark.parametrize(
    ("tamper", "code"),
    [
        (lambda ls: ls[:-1], "ledger.unsealed"),
        (lambda ls: ls[:-2] + [ls[-2].replace('"steps":', '"steps":9')] + ls[-1:], "ledger.altered"),
        (lambda ls: ls[:1] + ls[2:], "ledger.truncated"),
    ],
)
def test_tampered_ledger_scores_zero(env, tmp_path, tamper, code):
    sub = _session(env, tmp_path, [he.answer_action(i, a) for i, a in enumerate(INSTANCE.quadrants)])
    path = sub / "ledger.jsonl"
    path.write_text("\n".join(tamper(path.read_text().splitlines())) + "\n")
    report = hv.verify(sub, VerifyContext(secret=PUBLIC))
    assert report.score == 0.0 and not report.valid and report.errors[0].code == code


def test_a_ledger_replayed_on_another_instance_is_refused(env, tmp_path):
    # the same key, a ledger recorded on another scene: refused before any answer is read
    other = he.make_env(he.HiddenComInstance(("A", "A", "A"), (0, 0, 0)), image_size=None)
    sub = _session(other, tmp_path, [he.answer_action(0, "A")])
    report = hv.verify(sub, VerifyContext(secret=PUBLIC))
    assert report.score == 0.0 and report.errors[0].code == "replay.other_scene"


def test_an_answer_after_the_box_budget_is_refused_as_late():
    # steps_per_box shortened to 5 for speed; the task uses the card's 12,000 (pinned below)
    assert he.STEPS_PER_BOX == 12_000 and hc.HIDDEN_COM_STEPS == 3 * he.STEPS_PER_BOX
    short = he.HiddenComEnv(xml=he.scene_xml(INSTANCE), image_size=None, steps_per_box=5)
    model = short.build()
    short.prepare(model)
    data = mujoco.MjData(model)
    short.reset(model, data)  # 1 charged step
    for _ in range(3):
        short.step(model, data, zero_action())  # 4 charged steps
    assert short.observe(model, data)["answers"]["steps_left"] == 1
    short.step(model, data, he.answer_action(0, "A"))  # the 5th step: in time, the count restarts
    assert short.observe(model, data)["answers"]["steps_left"] == 5
    for _ in range(5):
        short.step(model, data, zero_action())
    short.reset(model, data)  # resets count too: 6 steps since the answer
    short.step(model, data, he.answer_action(1, "B"))  # 7th: late, refused
    assert he.recorded_answers(data) == ("A", None, None)
    assert he.answers_observation(model, data) == {"given": [True, False, False], "invalid": 0, "late": 1}


def test_a_session_without_the_cards_hour_is_refused(env, tmp_path):
    actions = [he.answer_action(i, a) for i, a in enumerate(INSTANCE.quadrants)]
    for limit in (None, 2 * hc.HIDDEN_COM_WALL_TIME_S):
        sub = _session(env, tmp_path / str(limit), actions, wall_time_s=limit)
        report = hv.verify(sub, VerifyContext(secret=PUBLIC))
        assert report.score == 0.0 and report.errors[0].code == "ledger.wrong_limits"
        assert f"{limit!r} s" in report.errors[0].message
