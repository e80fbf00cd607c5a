"""Printed parts: wall thickness by inward rays, build volume, overhangs; manifold3d booleans; CoACD."""

import time

import numpy as np
import pytest
import trimesh

from rle_design.errors import MjcfError
from rle_design.mjcf.mesh import boolean, check_mesh_bytes, collision_hulls, min_wall_thickness
from rle_design.mjcf.printability import overhang_fraction, printability_report

OUTER = np.array([0.040, 0.030, 0.020])  # [m]


def hollow_box(wall: float) -> trimesh.Trimesh:
    """Closed box with a closed inner cavity: outer - (outer - 2 wall), by manifold3d."""
    return boolean(trimesh.creation.box(OUTER), trimesh.creation.box(OUTER - 2 * wall), "difference")


def test_boolean_volumes_are_exact():
    wall = 0.002
    shell = hollow_box(wall)
    assert shell.is_watertight
    # V = V_outer - V_inner
    assert shell.volume == pytest.approx(np.prod(OUTER) - np.prod(OUTER - 2 * wall), rel=1e-9)
    a, b = trimesh.creation.box([1, 1, 1]), trimesh.creation.box([1, 1, 1]).apply_translation([0.5, 0, 0])
    assert boolean(a, b, "union").volume == pytest.approx(1.5, rel=1e-9)
    assert boolean(a, b, "intersection").volume == pytest.approx(0.5, rel=1e-9)
    with pytest.raises(MjcfError) as info:
        boolean(a, b, "xor")
    assert str(info.value) == "boolean op 'xor' does not exist. Available: union, difference, intersection"


@pytest.mark.parametrize("wall", [0.0004, 0.002])
def test_wall_thickness_of_a_hollow_box(wall):
    # parallel walls: every inward ray that crosses one wall has length exactly `wall`
    result = min_wall_thickness(hollow_box(wall), n_samples=500, seed=1)
    assert result.minimum == pytest.approx(wall, abs=1e-7)
    assert result.p05 == pytest.approx(wall, abs=1e-7)
    assert result.n_samples == 500


def test_thin_wall_fails_and_thick_wall_passes_the_pla_rules():
    thin = printability_report(hollow_box(0.0004), "pla", n_samples=500)
    assert not thin.passed
    assert thin.reasons == ("minimum wall 0.400 mm < 0.800 mm",)
    assert thin.min_wall_rule == 0.0008 and thin.fits and thin.watertight
    thick = printability_report(hollow_box(0.002), "pla", n_samples=500)
    assert thick.passed and thick.reasons == ()
    assert thick.min_wall == pytest.approx(0.002, abs=1e-7)
    # mass = rho (V_outer - V_inner), PLA 1240 kg/m^3
    assert thick.mass == pytest.approx(1240 * (np.prod(OUTER) - np.prod(OUTER - 0.004)), rel=1e-9)


def test_build_volume_orientations():
    # 240 mm long: fits only standing up (bed 220 x 220, height 250)
    bar = trimesh.creation.box([0.240, 0.010, 0.010])
    report = printability_report(bar, n_samples=200)
    assert report.fits and report.up in ("+x", "-x") and report.passed
    too_long = printability_report(trimesh.creation.box([0.300, 0.010, 0.010]), n_samples=200)
    assert not too_long.fits and too_long.up == ""
    assert too_long.reasons == (
        "part 300.0 x 10.0 x 10.0 mm does not fit the build volume 220 x 220 x 250 mm in any axis-aligned orientation",
    )


def table_shape() -> trimesh.Trimesh:
    """Leg 10 x 10 x 20 mm under a slab 40 x 40 x 5 mm (z up)."""
    leg = trimesh.creation.box([0.010, 0.010, 0.020]).apply_translation([0, 0, 0.010])
    slab = trimesh.creation.box([0.040, 0.040, 0.005]).apply_translation([0, 0, 0.0225])
    return boolean(leg, slab, "union")


def test_overhang_fraction_closed_form():
    part = table_shape()
    # overhang = slab underside minus leg top = 1600 - 100 = 1500 mm^2; the leg foot is on the bed.
    # total = slab (2 * 1600 + 4 * 40 * 5 - 100) + leg (4 * 10 * 20 + 100) = 3900 + 900 = 4800 mm^2
    assert part.area == pytest.approx(4800e-6, rel=1e-9)
    assert overhang_fraction(part, (0, 0, 1), 45.0, 0.0002) == pytest.approx(1500 / 4800, rel=1e-9)
    # upside down the slab lies on the bed and nothing overhangs
    assert overhang_fraction(part, (0, 0, -1), 45.0, 0.0002) == 0.0
    report = printability_report(part, n_samples=300)
    assert report.up == "-z" and report.overhang_fraction == 0.0


def test_open_mesh_is_not_watertight():
    box = trimesh.creation.box([0.02, 0.02, 0.02])
    open_box = trimesh.Trimesh(box.vertices, box.faces[:-2])
    report = printability_report(open_box, n_samples=200)
    assert not report.watertight and not report.passed
    assert "mesh is not watertight (open or non-manifold surface)" in report.reasons


def test_unknown_material_lists_the_catalog():
    with pytest.raises(Exception) as info:
        printability_report(trimesh.creation.box([0.01] * 3), material="abs")
    assert (
        str(info.value) == "materials entry 'abs' does not exist. Available: aluminium_6063, petg, pla, steel"
    )


def test_collision_hulls_of_an_l_shape_are_convex_and_fast():
    a = trimesh.creation.box([0.10, 0.02, 0.02]).apply_translation([0.05, 0.01, 0.01])
    b = trimesh.creation.box([0.02, 0.10, 0.02]).apply_translation([0.01, 0.05, 0.01])
    l_shape = boolean(a, b, "union")
    start = time.perf_counter()
    hulls = collision_hulls(l_shape, threshold=0.05)
    elapsed = time.perf_counter() - start
    assert 2 <= len(hulls) <= 16 and elapsed < 10.0
    for h in hulls:
        assert h.is_convex or np.isclose(h.volume, h.convex_hull.volume, rtol=1e-6)
    # the pieces cover the L (volume 2 * 0.1 * 0.02 * 0.02 - 0.02^3) within 10 %
    assert sum(h.volume for h in hulls) == pytest.approx(2 * 0.1 * 0.02 * 0.02 - 0.02**3, rel=0.10)


def test_check_mesh_bytes_counts_obj_faces():
    obj = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"
    assert check_mesh_bytes(obj, "t.obj", None, 10) == 4
    with pytest.raises(MjcfError) as info:
        check_mesh_bytes(obj, "t.obj", None, 3)
    assert (info.value.code, str(info.value)) == ("mesh.too_many_faces", "mesh has 4 faces, limit 3")
    with pytest.raises(MjcfError) as info:
        check_mesh_bytes(b"f 1 2 3\n", "t.obj", None, 3)
    assert str(info.value) == "not a valid OBJ: no vertex ('v') line"
