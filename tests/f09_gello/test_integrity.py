"""Issue-19 regressions on 09: passive effects that are not compensation, and diverging simulations.

Each artifact here used to score well (tendon friction on the stock leaders: about 0.60, valid, no
error; tendon damping 100 with the zero trim: about 0.37 through a diverged simulation); now each is
refused or failed for its named reason, and the honest reference still passes.
"""

import shutil

import mujoco
import numpy as np
import pytest
from lxml import etree

from rle_tasks.core.registry import get_task
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.core.solutions import materialise
from rle_tasks.core.task import VerifyContext
from rle_tasks.core.verify import run_verify
from rle_tasks.f09_gello import battery
from rle_tasks.f09_gello.leaders import ROBOTS
from rle_tasks.f09_gello.submission import load_submission, springs_summary

TASK = get_task("09-gello")


def _edit(directory, robot, edit):
    path = directory / robot / "lead.xml"
    tree = etree.parse(str(path))
    edit(tree.getroot())
    tree.write(str(path))


def _friction_tendons(root):
    """A fixed tendon per joint with frictionloss 1.2 N m: holds any pose, compensates nothing."""
    tendon = etree.SubElement(root, "tendon")
    for j in root.iter("joint"):
        if j.get("name"):
            fixed = etree.SubElement(tendon, "fixed", name=f"hold_{j.get('name')}", frictionloss="1.2")
            etree.SubElement(fixed, "joint", joint=j.get("name"), coef="1")


def _damping_spring(root):
    """The reference's shoulder spring with tendon damping 100 N s/m."""
    for spatial in root.iter("spatial"):
        spatial.set("damping", "100")


@pytest.mark.parametrize(
    "edit, codes",
    [
        (_friction_tendons, {"contract.fixed_tendon", "contract.tendon_friction"}),
        (_damping_spring, {"contract.tendon_damping"}),
    ],
)
def test_tendon_friction_and_damping_are_refused_by_name(tmp_path, edit, codes):
    src = materialise(TASK, "reference" if edit is _damping_spring else "baseline/uncompensated")
    d = shutil.copytree(src, tmp_path / "sub")
    _edit(d, "ur5e", edit)
    sub = load_submission("ur5e", d / "ur5e")
    assert not sub.usable
    assert codes <= {f.code for f in sub.structure}
    assert all("tendon '" in f.message for f in sub.structure if f.code in codes)


def test_springs_are_listed(tmp_path):
    sub = load_submission("ur5e", materialise(TASK, "reference") / "ur5e")
    springs = springs_summary(sub.model)
    assert sub.usable and springs and all(s["stiffness_N_per_m"] > 0 for s in springs if "tendon" in s)


def test_tendon_friction_on_stock_leaders_no_longer_scores(tmp_path):
    d = shutil.copytree(materialise(TASK, "baseline/uncompensated"), tmp_path / "sub")
    for robot in ROBOTS:
        _edit(d, robot, _friction_tendons)
    report, internal = run_verify(TASK, d, VerifyContext(secret=Secret(PUBLIC_KEY, public=True), quick=True))
    assert not internal
    codes = {e.code for e in report.errors}
    assert {"contract.fixed_tendon", "contract.tendon_friction"} <= codes
    assert not report.valid
    # the passive and combined checkpoints are unavailable (structure failure): at most the adapted
    # reference-arm checkpoints (20 %) and nothing from friction
    assert report.score < 0.25, report.score


def _diverging_model() -> mujoco.MjModel:
    # A 1 g point 0.1 m off a hinge of 1e9 N m/rad at dt = 2 ms: omega dt = sqrt(k / I) dt
    # = sqrt(1e9 / (1e-3 * 0.1^2)) * 2e-3 ~ 1.3e4 >> 2, so explicit integration diverges (mjWARN_BADQACC).
    spec = mujoco.MjSpec()
    body = spec.worldbody.add_body(pos=[0, 0, 0])
    body.add_joint(type=mujoco.mjtJoint.mjJNT_HINGE, axis=[0, 1, 0], stiffness=1e9)
    body.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[0.005, 0, 0], pos=[0.1, 0, 0], mass=1e-3)
    spec.option.timestep = 0.002
    return spec.compile()


def test_a_diverging_scenario_fails_with_the_warning_name():
    m = _diverging_model()
    q0, ff = np.array([0.1]), np.zeros(1)
    with pytest.raises(battery.SimulationFailed, match="mjWARN_BADQACC"):
        battery.hold_drift(m, q0, ff, 0.5)
    with pytest.raises(battery.SimulationFailed, match="mjWARN_BADQACC"):
        battery.breakaway(m, q0, ff, 0, 1.0, 0.1)
    # the same scenario on a stable hinge (k = 1 N m/rad) runs without a warning
    m.jnt_stiffness[0] = 1.0
    assert battery.hold_drift(m, q0, ff, 0.5) > 0.0


def _dense_geom_on_link2(root):
    """A dense, non-colliding geom on a stock body: it used to change nothing in the report."""
    link2 = next(b for b in root.iter("body") if b.get("name") == "link2")
    etree.SubElement(
        link2, "geom", name="dense_extra", type="box", size="0.01 0.01 0.01", density="100000",
        contype="0", conaffinity="0",
    )  # fmt: skip


def _extra_root_with_joint(root):
    """A second root body with its own hinge: it used to fault inside the verifier (a shape error)."""
    body = etree.Element("body", name="extra", pos="0.3 0 0.1")
    root.find("worldbody").insert(0, body)  # the first root: its joint comes before the leader's
    etree.SubElement(body, "joint", name="extra_j", type="hinge", axis="0 1 0")
    etree.SubElement(body, "geom", type="box", size="0.02 0.02 0.02", mass="0.1")


@pytest.mark.parametrize(
    "edit, codes",
    [
        (_dense_geom_on_link2, {"contract.stock_body_addition"}),
        (_extra_root_with_joint, {"contract.multiple_roots", "contract.extra_joint"}),
    ],
)
def test_additions_the_contract_does_not_name_are_refused_by_name(tmp_path, edit, codes):
    d = shutil.copytree(materialise(TASK, "reference"), tmp_path / "sub")
    for robot in ROBOTS:
        _edit(d, robot, edit)
    ctx = VerifyContext(secret=Secret(PUBLIC_KEY, public=True), quick=True, out_dir=tmp_path / "figs")
    report, internal = run_verify(TASK, d, ctx)  # with figures: the render once faulted on such a leader
    assert not internal, report.errors
    assert codes <= {e.code for e in report.errors}
    assert not report.valid and report.score <= 0.2 + 1e-9, report.score
