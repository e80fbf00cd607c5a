"""Family 08: reference and baselines through the verifier (quick batteries), harness, determinism.

The quick reports use the public development key, the secret of the golden table
(``rle_tasks/f08_mobile_base/solutions``): each shipped solution's score must equal its golden score.
"""

import functools
import os
import subprocess
import sys
from pathlib import Path

import pytest

from rle_tasks.core.registry import get_task
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.core.solutions import declaration, materialise
from rle_tasks.core.task import VerifyContext
from rle_tasks.f08_mobile_base.scoring import CAP, RUBRIC, WEIGHTS
from rle_tasks.f08_mobile_base.verifier import verify

SECRET = Secret(PUBLIC_KEY, public=True)
TASK = get_task("08-mobile-base")


@functools.cache
def _report(name: str):
    return verify(materialise(TASK, name), VerifyContext(secret=SECRET, quick=True))


def test_task_registered_with_contract_and_budget():
    t = get_task("08-mobile-base")
    assert t.implemented and t.contract.required == ("robot.xml", "controller.py")
    assert t.budget.wall_time_s == 7200 and t.budget.cpus == 4
    assert set(t.solutions) >= {"reference", "baseline/tall_narrow", "baseline/raising_controller"}


def test_weights_match_the_card():
    assert WEIGHTS == {
        "validity": 0.15,
        "design_resources": 0.35,
        "static_stability": 0.15,
        "dynamic_stability": 0.20,
        "shelf_1kg": 0.10,
        "shelf_2kg": 0.05,
    }


@pytest.mark.physics
def test_reference_report_has_every_checkpoint_per_arm():
    r = _report("reference")
    assert [c.id for c in r.checkpoints] == list(WEIGHTS)
    for c in r.checkpoints:
        assert set(c.per_variant) == {"panda", "ur5e", "xarm7"}
        assert c.score == pytest.approx(min(c.per_variant.values()))
    assert r.valid and r.cap is None
    assert r.checkpoint("validity").score == 1.0


@pytest.mark.physics
def test_reference_scores_at_least_075(full_battery):
    r = (
        _report("reference")
        if not full_battery
        else verify(materialise(TASK, "reference"), VerifyContext(secret=SECRET, jobs=2))
    )
    assert r.score >= 0.75 and r.cap is None


@pytest.mark.physics
def test_tall_narrow_fails_static_stability_with_2kg():
    r = _report("baseline/tall_narrow")
    # its tower's four posts stand through the battery (welded parts, never collided by MuJoCo):
    # refused by name since issue 45, the batteries still measured
    assert r.checkpoint("validity").score == 0.0 and {e.code for e in r.errors} == {"f08.interpenetration"}
    assert all("into 'battery_geom' of body 'battery' (welded to it;" in e.message for e in r.errors)
    c = r.checkpoint("static_stability")
    assert c.score < 0.5 and any("@2kg" in f for m in c.measured.values() for f in m["failed"])
    assert r.score <= CAP


@pytest.mark.physics
def test_non_catalog_profile_fails_validity():
    r = _report("baseline/non_catalog_profile")
    assert r.checkpoint("validity").score == 0.0 and r.cap == CAP
    assert any(
        e.code == "catalog.unknown_profile"
        and e.message
        == "geom 'profile_5050_rail_left': profile '5050' is not in the catalog. "
        "Available profiles: 2020, 2040, 3030, 4040, 4080"
        for e in r.errors
    )


@pytest.mark.physics
def test_bad_mount_fails_shelf_integration():
    r = _report("baseline/bad_mount")
    assert r.checkpoint("validity").score == 1.0
    assert r.checkpoint("shelf_1kg").score == 0.0 and r.checkpoint("shelf_2kg").score == 0.0
    # the targets are out of reach: IK residuals of several decimetres for every arm
    assert all(max(res.values()) > 0.2 for res in r.native_metrics["ik_residual_m"].values())
    assert r.cap == CAP and r.native_metrics["cap_reason"] == "required 1 kg load"


@pytest.mark.physics
def test_raising_controller_fails_shelf_with_exception_text():
    r = _report("baseline/raising_controller")
    assert r.checkpoint("shelf_1kg").score == 0.0
    assert "RuntimeError: controller deliberately failed: no motion plan" in r.checkpoint("shelf_1kg").message
    assert any(e.code == "sandbox.exception" for e in r.errors)
    assert r.cap == CAP and r.score <= CAP


def test_dev_env_lays_out_harness(tmp_path: Path):
    get_task("08-mobile-base").make_dev_env(tmp_path)
    for rel in (
        "instruction.md",
        "skeleton_robot.xml",
        "mobile_base/scene.py",
        "mobile_base/preview.py",
        "catalog/profiles.yaml",
        "catalog/shelf.yaml",
        "catalog/parts/mecanum_wheel.xml",
        "arms/panda/robot.xml",
        "arms/ur5e/robot.xml",
        "arms/xarm7/robot.xml",
    ):
        assert (tmp_path / rel).is_file(), rel
    text = (tmp_path / "instruction.md").read_text()
    assert "arm_mount_site" in text and RUBRIC.markdown_table() in text


@pytest.mark.render
def test_workspace_preview_runs_from_the_workspace(tmp_path: Path):
    """The public preview imports only the toolkit and its own package: it runs in the workspace."""
    get_task("08-mobile-base").make_dev_env(tmp_path)
    robot = materialise(TASK, "reference") / "robot.xml"
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    out = subprocess.run(
        [sys.executable, "-m", "mobile_base.preview", str(robot), "--arm", "ur5e", "--png", "p.png"],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert out.returncode == 0, out.stderr
    assert "wrote p.png" in out.stdout and (tmp_path / "p.png").stat().st_size > 10_000


def test_missing_robot_xml_is_a_validity_failure(tmp_path: Path):
    (tmp_path / "controller.py").write_text("def reset(*a): pass\ndef control(*a): return []\n")
    r = verify(tmp_path, VerifyContext(secret=SECRET, quick=True))
    assert r.checkpoint("validity").score == 0.0 and r.cap == CAP and r.score <= CAP


@pytest.mark.physics
def test_same_artifact_and_secret_give_identical_report():
    a = verify(materialise(TASK, "baseline/raising_controller"), VerifyContext(secret=SECRET, quick=True))
    a = a.to_dict()
    b = _report("baseline/raising_controller").to_dict()
    a.pop("elapsed_s"), b.pop("elapsed_s")
    assert a == b


def test_hidden_variations_follow_the_secret():
    from rle_tasks.f08_mobile_base.verifier import _variation

    ctx_a = VerifyContext(secret=SECRET)
    ctx_b = VerifyContext(secret=Secret(b"other", public=False))
    assert _variation(ctx_a, "panda/static/1") == _variation(ctx_a, "panda/static/1")
    assert _variation(ctx_a, "panda/static/1") != _variation(ctx_b, "panda/static/1")


@pytest.mark.physics
@pytest.mark.parametrize("name", TASK.solutions)
def test_quick_score_equals_the_golden_table(name):
    r = _report(name)
    assert r.score == pytest.approx(declaration(TASK).get(name).quick_score, abs=1e-9)
