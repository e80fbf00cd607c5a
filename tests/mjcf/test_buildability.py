"""Build-ability audit pinned by closed-form gaps between simple solids."""

import mujoco
import pytest

from rle_design.mjcf.buildability import audit_buildability, geom_gap


def _model(*geoms_by_body) -> mujoco.MjModel:
    """Bodies nested in order (each the child of the previous), each with its (type, size, pos) geoms."""
    spec = mujoco.MjSpec()
    parent = spec.worldbody
    for i, geoms in enumerate(geoms_by_body):
        body = parent.add_body(name=f"b{i}", pos=[0, 0, 0])
        for j, (kind, size, pos) in enumerate(geoms):
            body.add_geom(name=f"b{i}_g{j}", type=kind, size=size, pos=pos, mass=0.1)
        parent = body
    return spec.compile()


BOX, SPHERE, CYL = mujoco.mjtGeom.mjGEOM_BOX, mujoco.mjtGeom.mjGEOM_SPHERE, mujoco.mjtGeom.mjGEOM_CYLINDER


@pytest.mark.parametrize("gap", [0.005, 0.02])
def test_a_part_away_from_its_body_is_reported_with_its_gap(gap):
    # two 0.1 m cubes (half size 0.05) with centres 0.1 + gap apart: surface gap = gap
    m = _model([(BOX, [0.05, 0.05, 0.05], [0, 0, 0]), (BOX, [0.05, 0.05, 0.05], [0.1 + gap, 0, 0])])
    (d,) = audit_buildability(m)
    assert d.kind == "part" and d.body == "b0" and d.gap_m == pytest.approx(gap, abs=1e-9)
    assert f"{gap * 1e3:.1f} mm" in d.message


def test_touching_or_overlapping_parts_form_one_assembly():
    touching = [(BOX, [0.05, 0.05, 0.05], [0, 0, 0]), (BOX, [0.05, 0.05, 0.05], [0.1, 0, 0])]
    overlapping = [(SPHERE, [0.05, 0, 0], [0, 0, 0]), (SPHERE, [0.05, 0, 0], [0.08, 0, 0])]
    chain = [(BOX, [0.05, 0.05, 0.05], [0.1 * k, 0, 0]) for k in range(4)]  # joined through neighbours
    for geoms in (touching, overlapping, chain):
        assert audit_buildability(_model(geoms)) == []


def test_gaps_follow_the_closed_forms():
    # spheres: |c1 - c2| - r1 - r2 = 0.3 - 0.05 - 0.1 = 0.15; cylinder (axis z, r 0.05, half 0.1) to a
    # box above it: 0.5 - 0.1 - 0.05 = 0.35
    m = _model(
        [
            (SPHERE, [0.05, 0, 0], [0, 0, 0]),
            (SPHERE, [0.1, 0, 0], [0.3, 0, 0]),
            (CYL, [0.05, 0.1, 0], [0, 1, 0]),
            (BOX, [0.05, 0.05, 0.05], [0, 1, 0.5]),
        ]
    )
    d = mujoco.MjData(m)
    mujoco.mj_kinematics(m, d)
    assert geom_gap(m, d, 0, 1) == pytest.approx(0.15, abs=1e-9)
    assert geom_gap(m, d, 2, 3) == pytest.approx(0.35, abs=1e-6)


def test_a_child_body_must_meet_its_parent_unless_allowed():
    # child cube 3 mm from the parent cube: reported at 1 mm tolerance, accepted with a 5 mm allowance
    parent = [(BOX, [0.05, 0.05, 0.05], [0, 0, 0])]
    child = [(BOX, [0.05, 0.05, 0.05], [0.103, 0, 0])]
    m = _model(parent, child)
    (d,) = audit_buildability(m)
    assert d.kind == "body" and d.body == "b1" and d.gap_m == pytest.approx(0.003, abs=1e-9)
    assert audit_buildability(m, parent_tol={"b1": 0.005}) == []
    assert audit_buildability(m, bodies=["b0"]) == []
