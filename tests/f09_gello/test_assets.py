"""The shipped stock leaders: compile, step, sag as specified, masses from printed shells."""

from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin
import pytest
import trimesh

from rle_design.kinematics import GravityMap, model_from_mujoco
from rle_tasks.core.registry import get_task
from rle_tasks.core.solutions import materialise
from rle_tasks.f09_gello.device import ASSET_DIR
from rle_tasks.f09_gello.leaders import ROBOTS, SCALE, pla_density, servo
from rle_tasks.f09_gello.public.gello_helpers import workspace_grid

PKG = ASSET_DIR.parent
TASK = get_task("09-gello")
# Stock leaders and every leader of every materialised shipped solution, by "<solution>/<robot>".
LEADERS = {f"assets/{r}": ASSET_DIR / r / "lead.xml" for r in ROBOTS} | {
    f"{name}/{r}": materialise(TASK, name) / r / "lead.xml" for name in TASK.solutions for r in ROBOTS
}
XMLS = sorted(LEADERS)


@pytest.mark.parametrize("rel", XMLS)
def test_every_shipped_leader_compiles_and_steps_one_second_without_warnings(rel):
    m = mujoco.MjModel.from_xml_path(str(LEADERS[rel]))
    d = mujoco.MjData(m)
    rng = np.random.default_rng(0)
    for _ in range(500):
        d.qfrc_applied[:] = rng.normal(0, 0.01, m.nv)
        mujoco.mj_step(m, d)
    assert all(w.number == 0 for w in d.warning), [(i, w.number) for i, w in enumerate(d.warning) if w.number]
    assert np.all(np.isfinite(d.qpos))


def test_meshes_are_small():
    sizes = {str(p.relative_to(PKG)): p.stat().st_size for p in PKG.rglob("*.stl")}
    assert sizes and max(sizes.values()) < 200_000


@pytest.mark.parametrize("robot", ROBOTS)
def test_stock_leader_sags_about_three_times_the_servo_limit(robot):
    m = mujoco.MjModel.from_xml_path(str(ASSET_DIR / robot / "lead.xml"))
    km = model_from_mujoco(m)
    peak = np.abs(GravityMap(km)(workspace_grid(m.jnt_range, 4096))).max(axis=0)
    limit = servo().torque_limit
    assert 2.5 * limit < peak[1] < 3.5 * limit  # shoulder
    assert peak[0] < 1e-9  # joint 1 is vertical


@pytest.mark.parametrize("robot", ROBOTS)
def test_link_mass_is_printed_shell_volume_times_pla_density_plus_the_servo(robot):
    m = mujoco.MjModel.from_xml_path(str(ASSET_DIR / robot / "lead.xml"))
    for b in range(2, m.nbody):
        name = m.body(b).name
        stl = ASSET_DIR / robot / "meshes" / f"{name}.stl"
        shell = trimesh.load(stl).volume * pla_density() if stl.exists() else 0.0
        assert m.body_mass[b] == pytest.approx(shell + servo().mass, rel=1e-4)


GRAVCOMP_XMLS = [r for r in XMLS if "gravcomp_cheat" in str(r)]


@pytest.mark.parametrize("rel", [r for r in XMLS if r not in GRAVCOMP_XMLS])
def test_pinocchio_and_mujoco_gravity_agree(rel):
    m = mujoco.MjModel.from_xml_path(str(LEADERS[rel]))
    d = mujoco.MjData(m)
    km = model_from_mujoco(m)
    for q in workspace_grid(m.jnt_range, 50, seed=1):
        d.qpos[:] = q
        mujoco.mj_forward(m, d)
        assert np.max(np.abs(pin.computeGeneralizedGravity(km.model, km.data, q) - d.qfrc_bias)) < 1e-9


@pytest.mark.parametrize("rel", GRAVCOMP_XMLS)
def test_gravcomp_cheat_hides_gravity_from_mujoco_but_not_from_pinocchio(rel):
    # Why the contract rejects gravcomp: MuJoCo cancels the links' gravity by fiat (a passive force
    # qfrc_gravcomp equal to the bias at rest: net gravity torque 0), while Pinocchio (which drops
    # gravcomp) still sees the full g(q).
    m = mujoco.MjModel.from_xml_path(str(LEADERS[rel]))
    assert all(m.body_gravcomp[2:] == 1)
    d = mujoco.MjData(m)
    km = model_from_mujoco(m)
    q = workspace_grid(m.jnt_range, 8, seed=2)[3]
    d.qpos[:] = q
    mujoco.mj_forward(m, d)
    assert np.max(np.abs(d.qfrc_bias - d.qfrc_gravcomp)) < 1e-9
    assert np.max(np.abs(pin.computeGeneralizedGravity(km.model, km.data, q))) > 0.1


def test_ur5e_leader_is_the_follower_scaled_by_0_55():
    m = mujoco.MjModel.from_xml_path(str(ASSET_DIR / "ur5e" / "lead.xml"))
    d = mujoco.MjData(m)
    mujoco.mj_kinematics(m, d)
    anchors = d.xanchor
    assert np.linalg.norm(anchors[2] - anchors[1]) == pytest.approx(SCALE * 0.425, abs=1e-9)  # a2
    assert np.linalg.norm(anchors[3] - anchors[2]) == pytest.approx(SCALE * 0.3922, abs=1e-9)  # a3
    assert anchors[1][2] - anchors[0][2] == pytest.approx(SCALE * 0.1625, abs=1e-9)  # d1


def test_generated_assets_are_up_to_date(tmp_path: Path):
    from rle_tasks.f09_gello.assembly import build_assembly

    for robot in ROBOTS:
        assert build_assembly(robot).xml == (ASSET_DIR / robot / "lead.xml").read_text()
