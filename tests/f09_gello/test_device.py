"""Structure and validity checks of a submitted leader against the stock assembly; hidden copies."""

import shutil

import mujoco
import numpy as np
import pytest

from rle_design.scene import Variation, element_id
from rle_tasks.f09_gello.constants import HARD_MASS_KG, MAX_MASS_KG
from rle_tasks.f09_gello.device import (
    ASSET_DIR,
    apply_variation,
    battery_model,
    device_variations,
    stock_model,
)
from rle_tasks.f09_gello.scoring import RUBRIC
from rle_tasks.f09_gello.submission import deductions, load_submission


def _variant(tmp_path, old: str, new: str, robot: str = "ur5e"):
    d = tmp_path / robot
    shutil.copytree(ASSET_DIR / robot, d)
    text = (d / "lead.xml").read_text()
    assert old in text
    (d / "lead.xml").write_text(text.replace(old, new, 1))
    return load_submission(robot, d)


def _codes(sub) -> list[str]:
    return [f.code for f in sub.structure + sub.validity]


def test_stock_leader_is_clean(tmp_path):
    for robot in ("panda", "ur5e", "xarm7"):
        d = shutil.copytree(ASSET_DIR / robot, tmp_path / robot)  # copies follow the shared-mesh links
        sub = load_submission(robot, d)
        assert sub.usable and not sub.validity
        assert sub.mass < 0.6


def test_the_shared_base_mesh_is_stored_once_and_copies_are_self_contained(tmp_path):
    """The package keeps one base plate mesh; a leader directory in the package is not a submission
    (its link leaves it), a copy of it is."""
    common = ASSET_DIR / "common" / "meshes" / "base.stl"
    assert common.is_file() and not common.is_symlink()
    for robot in ("panda", "ur5e", "xarm7"):
        link = ASSET_DIR / robot / "meshes" / "base.stl"
        assert link.is_symlink() and link.resolve() == common.resolve()
    assert "artifact.symlink_escape" in _codes(load_submission("ur5e", ASSET_DIR / "ur5e"))
    d = shutil.copytree(ASSET_DIR / "ur5e", tmp_path / "ur5e")
    assert not (d / "meshes" / "base.stl").is_symlink()
    assert (d / "meshes" / "base.stl").read_bytes() == common.read_bytes()


@pytest.mark.parametrize(
    "old, new, code",
    [
        ('<body name="link3" pos="-0.23375', '<body name="link3" pos="-0.2', "contract.joint_frame"),
        ('range="-2.8 2.8"', 'range="-2.8 2.0"', "contract.joint_frame"),
        ('range="-2.8 2.8"', 'range="-2.8 2.8" ref="0.3"', "contract.joint_frame"),
        ('frictionloss="0.0128"', 'frictionloss="0.05"', "contract.stock_servo"),
        ('<body name="link2"', '<body name="link2" gravcomp="1"', "contract.gravcomp"),
        ("<worldbody>", '<option gravity="0 0 -1"/><worldbody>', "contract.option_changed"),
        ("</worldbody>", '</worldbody><actuator><motor joint="j2"/></actuator>', "contract.actuator"),
        ("</worldbody>", '</worldbody><equality><weld body1="link2"/></equality>', "contract.world_weld"),
        ('<geom name="link2_shell" class="printed" mesh="link2"/>', "", "contract.stock_geometry"),
        (
            '<site name="handle_site"',
            '<body name="x"><joint name="extra" axis="1 0 0"/><geom size="0.01"/></body><site name="handle_site"',
            "contract.extra_joint",
        ),
        (
            '<mesh name="base" file="base.stl"/>',
            '<mesh name="base" file="../../base.stl"/>',
            "artifact.path_escape",
        ),
    ],
)
def test_structure_violations_are_named(tmp_path, old, new, code):
    sub = _variant(tmp_path, old, new)
    assert code in [f.code for f in sub.structure], _codes(sub)
    assert not sub.usable


def test_inertial_change_of_a_stock_link_is_refused(tmp_path):
    sub = _variant(tmp_path, 'mass="0.086338"', 'mass="0.050000"')
    assert [f.code for f in sub.structure] == ["contract.stock_inertia"]
    assert "stock body 'link2' inertial changed" in sub.structure[0].message


def test_a_point_mass_is_refused_and_over_mass_deducted(tmp_path):
    # 2.5 kg declared in a body with no parts: no material has that density (it is not steel)
    block = '<body name="lead" pos="0 0 0.05"><inertial pos="0 0 0" mass="2.5" diaginertia="1e-4 1e-4 1e-4"/></body>'
    sub = _variant(tmp_path, '<site name="mount_site"', block + '<site name="mount_site"')
    assert not sub.usable
    assert "contract.com_outside" in {f.code for f in sub.structure}
    assert [f.code for f in sub.validity] == ["contract.over_mass"]
    assert sub.validity[0].message.startswith("device mass 2.947 kg exceeds 2.30 kg")
    # the deduction grows with the excess: (2.947 - 2.30) / (3.00 - 2.30) = 0.924 of 0.10
    assert deductions(sub) == [("contract.over_mass", pytest.approx(0.647 / 0.70, abs=2e-3))]
    assert RUBRIC.deduction(deductions(sub)) == pytest.approx(0.0924, abs=2e-4)


@pytest.mark.parametrize(("extra_kg", "code"), [(2.2, None), (3.0, "contract.mass_bound")])
def test_the_over_mass_deduction_is_linear_up_to_the_hard_bound(tmp_path, extra_kg, code):
    # a steel cube of the extra mass on the base: side = (m / 7850)^(1/3), so no point-mass finding
    side = (extra_kg / 7850.0) ** (1 / 3)
    # resting on the base plate (its top face is the base frame's z = 0), 1 mm into it: fastened
    block = f'<body name="lead" pos="0 0 {side / 2 - 0.001}"><geom type="box" size="{side / 2} {side / 2} {side / 2}" mass="{extra_kg}"/></body>'
    sub = _variant(tmp_path, '<site name="mount_site"', block + '<site name="mount_site"')
    if code is None:  # stock ur5e 0.447 kg + 2.2 kg = 2.647 kg: (2.647 - 2.30) / 0.70 = 0.496 of 0.10
        assert sub.usable and [f.code for f in sub.validity] == ["contract.over_mass"]
        expected = (sub.mass - MAX_MASS_KG) / (HARD_MASS_KG - MAX_MASS_KG) * 0.10
        assert RUBRIC.deduction(deductions(sub)) == pytest.approx(expected) == pytest.approx(0.0496, abs=1e-3)
    else:
        assert [f.code for f in sub.structure] == [code] and not sub.usable


def test_hidden_copy_scales_link_masses_and_adds_the_payload():
    m = stock_model("panda")
    scale = (1.1, 0.9, 1.0, 1.15, 0.85, 1.0, 1.05)
    space = device_variations(7)
    var = Variation(space.terms, (scale, (0.03,)))
    h = apply_variation(m, var)
    expected = m.body_mass[1] + sum(f * m.body_mass[k + 2] for k, f in enumerate(scale)) + 0.03
    assert h.body_mass.sum() == pytest.approx(expected, rel=1e-12)
    # the payload sits at the handle site: static torque check against a model with an explicit mass
    d = mujoco.MjData(h)
    mujoco.mj_forward(h, d)
    sid = element_id(h, "site", "handle_site")
    b = h.site_bodyid[sid]
    c_expected = (m.body_mass[b] * 1.05 * m.body_ipos[b] + 0.03 * m.site_pos[sid]) / (
        m.body_mass[b] * 1.05 + 0.03
    )
    assert np.allclose(h.body_ipos[b], c_expected, atol=1e-12)
    assert m.body_mass.sum() != h.body_mass.sum()  # the stock model is untouched
    assert stock_model("panda").body_mass[b] == m.body_mass[b]


def test_battery_model_sets_noslip_and_disables_contacts():
    b = battery_model(stock_model("ur5e"))
    assert b.opt.noslip_iterations == 10 and b.opt.timestep == 0.002
    assert b.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_CONTACT
    assert stock_model("ur5e").opt.noslip_iterations == 0


def test_thin_added_part_is_not_printable(tmp_path):
    import trimesh

    d = tmp_path / "ur5e"
    shutil.copytree(ASSET_DIR / "ur5e", d)
    plate = trimesh.creation.box(extents=(0.05, 0.05, 0.0004))
    (d / "meshes" / "fin.stl").write_bytes(trimesh.exchange.stl.export_stl(plate))
    text = (d / "lead.xml").read_text()
    text = text.replace(
        '<mesh name="base" file="base.stl"/>',
        '<mesh name="base" file="base.stl"/><mesh name="fin" file="fin.stl"/>',
    )
    text = text.replace(  # a fin lying in the base plate (fastened, but too thin to print)
        '<site name="mount_site"',
        '<body name="fin" pos="0 0 -0.006"><geom name="fin" type="mesh" mesh="fin" density="1240"/></body><site name="mount_site"',
    )
    (d / "lead.xml").write_text(text)
    sub = load_submission("ur5e", d)
    assert sub.usable
    assert [f.code for f in sub.validity] == ["contract.printability"]
    assert "added part 'fin' is not printable: minimum wall 0.400 mm < 0.800 mm" in sub.validity[0].message


def test_exclude_cannot_hide_a_counterweight_collision(tmp_path):
    from rle_tasks.f09_gello.clearance import collision_fraction
    from rle_tasks.f09_gello.public.gello_helpers import workspace_grid

    d = tmp_path / "ur5e"
    shutil.copytree(ASSET_DIR / "ur5e", d)
    text = (d / "lead.xml").read_text()
    # a steel ball on a 12 cm arm at the shoulder sweeps through the table and the base
    ball = (  # on a printed rod back to the joint axis, so it is fastened to link 2
        '<body name="ball" pos="0.12 0 0"><geom name="ball" type="sphere" size="0.03" density="7850"/>'
        '<geom name="ball_rod" type="cylinder" fromto="0 0 0 -0.12 0 0" size="0.006" density="1240"/></body>'
    )
    text = text.replace('<joint name="j2"', ball + '<joint name="j2"', 1)
    excluded = text.replace(
        "</worldbody>",
        '</worldbody><contact><exclude body1="ball" body2="world"/><exclude body1="ball" body2="base"/></contact>',
    )
    grid = workspace_grid(
        np.array([[-3.14, 3.14], [-3.14, 0.0], [-2.8, 2.8], [-3.14, 3.14], [-3.14, 3.14], [-3.14, 3.14]]), 64
    )
    fractions = []
    for t in (text, excluded):
        (d / "lead.xml").write_text(t)
        sub = load_submission("ur5e", d)
        assert sub.usable, sub.structure
        fractions.append(collision_fraction(sub.design, ["ball"], grid)[0])
    assert fractions[0] > 0.0 and fractions[0] == fractions[1]
