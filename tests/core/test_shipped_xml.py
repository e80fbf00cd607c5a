"""Every shipped MJCF compiles and steps for 1 s without a MuJoCo warning.

Shipped XML: every ``*.xml`` package file of ``rle_design`` and ``rle_tasks`` (catalog parts, family
assets) and every XML of every materialised solution. Catalog parts are fixed bodies on
their own; they are attached with a free joint 0.3 m above a floor (MjSpec attach) so that they fall,
land and rest. Controls, where a model has actuators, are seeded uniform noise in their range.
"""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pytest

import rle_design
import rle_tasks
from rle_design.paths import CATALOG_DIR
from rle_tasks.core.registry import all_tasks
from rle_tasks.core.solutions import materialise

PACKAGES = (Path(rle_design.__file__).parent, Path(rle_tasks.__file__).parent)
# Committed solution files are checked as parts of their materialised solutions (meshes come from assets).
PACKAGE_XML = sorted(p for root in PACKAGES for p in root.rglob("*.xml") if "solutions" not in p.parts)
SOLUTIONS = [(t.id, name) for t in all_tasks() if t.implemented for name in t.solutions]
# Solutions that ship MJCF (estimators, policies and models alone have none to step).
MJCF_SOLUTIONS = [(t, n) for t, n in SOLUTIONS if any(materialise(t, n).rglob("*.xml"))]


def _in_floor_world(part: Path) -> mujoco.MjModel:
    world = mujoco.MjSpec()
    world.worldbody.add_geom(name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[2.0, 2.0, 0.1])
    child = mujoco.MjSpec.from_file(str(part))
    body = child.worldbody.first_body()
    body.add_freejoint()
    world.worldbody.add_frame(pos=[0.0, 0.0, 0.3]).attach_body(body, "part/", "")
    return world.compile()


def _warnings_after_one_second(m: mujoco.MjModel) -> dict[str, int]:
    d = mujoco.MjData(m)
    rng = np.random.default_rng(0)
    lo, hi = m.actuator_ctrlrange.T if m.nu else (np.zeros(0), np.zeros(0))
    for _ in range(int(round(1.0 / m.opt.timestep))):
        if m.nu:
            d.ctrl[:] = rng.uniform(np.where(np.isfinite(lo), lo, -1.0), np.where(np.isfinite(hi), hi, 1.0))
        mujoco.mj_step(m, d)
    return {
        mujoco.mjtWarning(i).name: int(d.warning[i].number)
        for i in range(mujoco.mjtWarning.mjNWARNING)
        if d.warning[i].number
    }


def test_the_shipped_xml_is_found():
    names = {p.relative_to(p.parents[1]).as_posix() for p in PACKAGE_XML}
    assert {"parts/battery.xml", "panda/lead.xml", "demo_assets/test_base.xml"} <= names
    assert len(SOLUTIONS) >= 10
    # the shipped designs of 08 and 09 hold MJCF: the step check below is not vacuous for them
    assert all(
        any(materialise(t, n).rglob("*.xml")) for t, n in SOLUTIONS if t in ("08-mobile-base", "09-gello")
    )


@pytest.mark.parametrize("path", PACKAGE_XML, ids=lambda p: p.relative_to(p.parents[2]).as_posix())
def test_package_xml_steps_one_second_without_warnings(path: Path):
    if path.is_relative_to(CATALOG_DIR / "parts"):
        m = _in_floor_world(path)
    else:
        m = mujoco.MjModel.from_xml_path(str(path))
    assert _warnings_after_one_second(m) == {}


@pytest.mark.parametrize(("task_id", "name"), MJCF_SOLUTIONS, ids=[f"{t}:{n}" for t, n in MJCF_SOLUTIONS])
def test_materialised_solution_xml_steps_one_second_without_warnings(task_id: str, name: str):
    files = sorted(materialise(task_id, name).rglob("*.xml"))
    assert files
    for path in files:
        assert _warnings_after_one_second(mujoco.MjModel.from_xml_path(str(path))) == {}, path


def test_the_check_reports_an_unstable_model(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # MuJoCo appends its warning to ./MUJOCO_LOG.TXT
    # A 1 g point 0.1 m off a hinge of 1e9 N m/rad at dt = 0.01 s diverges at once: mjWARN_BADQACC.
    spec = mujoco.MjSpec()
    spec.option.timestep = 0.01
    body = spec.worldbody.add_body()
    body.add_joint(type=mujoco.mjtJoint.mjJNT_HINGE, axis=[0, 1, 0], stiffness=1e9)
    body.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[0.01, 0, 0], pos=[0.1, 0, 0], mass=1e-3)
    assert _warnings_after_one_second(spec.compile()) == {"mjWARN_BADQACC": 1}
