"""Issue-19 regression on 08: a declared <inertial> that contradicts the geometry is invalid."""

import shutil

import pytest
from lxml import etree

from rle_design.mjcf import load_design
from rle_tasks.core.solutions import materialise
from rle_tasks.f08_mobile_base.validity import check_validity


def _with_chassis_inertial(tmp_path, pos: str, mass: float | None = None):
    d = shutil.copytree(materialise("08-mobile-base", "reference"), tmp_path / "sub")
    m = load_design(d).compile()
    total = float(m.body_mass[m.body("chassis").id]) if mass is None else mass
    path = d / "robot.xml"
    tree = etree.parse(str(path))
    chassis = next(b for b in tree.getroot().iter("body") if b.get("name") == "chassis")
    chassis.insert(0, etree.Element("inertial", pos=pos, mass=f"{total:.6f}", diaginertia="0.5 0.5 0.5"))
    tree.write(str(path))
    return load_design(d)


def test_the_reference_inertials_follow_from_its_geoms():
    assert check_validity(load_design(materialise("08-mobile-base", "reference"))) == []


def test_the_profiles_mass_with_a_centre_of_mass_below_the_floor_is_invalid(tmp_path):
    # the chassis' own mass, declared 0.5 m below its frame (under the floor): the exploit of the audit
    findings = check_validity(_with_chassis_inertial(tmp_path, "0 0 -0.5"))
    mismatch = [msg for code, msg in findings if code == "f08.inertial_mismatch"]
    assert len(mismatch) == 1 and "body 'chassis'" in mismatch[0] and "-0.5" in mismatch[0]


@pytest.mark.parametrize("mass", [1.0, 20.0])
def test_a_declared_mass_other_than_the_geometry_is_invalid(tmp_path, mass):
    findings = check_validity(_with_chassis_inertial(tmp_path, "0 0 0", mass))
    assert "f08.inertial_mismatch" in {c for c, _ in findings}


def test_a_catalog_part_with_its_centre_of_mass_moved_is_modified(tmp_path):
    d = shutil.copytree(materialise("08-mobile-base", "reference"), tmp_path / "sub")
    path = d / "robot.xml"
    tree = etree.parse(str(path))
    battery = next(b for b in tree.getroot().iter("body") if b.get("name") == "battery")
    battery.find("inertial").set("pos", "0 0 -0.2")  # the battery's 3.5 kg hung 0.2 m lower
    tree.write(str(path))
    findings = check_validity(load_design(d))
    assert any(c == "f08.part_modified" and "'battery'" in msg and "-0.2" in msg for c, msg in findings)


def _edited(tmp_path, edit):
    d = shutil.copytree(materialise("08-mobile-base", "reference"), tmp_path / "sub")
    path = d / "robot.xml"
    tree = etree.parse(str(path))
    edit(tree.getroot())
    tree.write(str(path))
    return load_design(d)


def _battery_in_mid_air(root):
    battery = next(b for b in root.iter("body") if b.get("name") == "battery")
    x, y, z = (float(v) for v in battery.get("pos").split())
    battery.set("pos", f"{x} {y} {z + 0.10}")  # 10 cm up: nothing holds it


def _floating_profile(root):
    chassis = next(b for b in root.iter("body") if b.get("name") == "chassis")
    etree.SubElement(
        chassis, "geom", name="profile_4040_float", type="box", size="0.1 0.02 0.02", pos="0 0 0.6",
        mass="0.348",
    )  # fmt: skip


def test_the_reference_frame_is_fastened_together():
    assert not [
        f
        for f in check_validity(load_design(materialise("08-mobile-base", "reference")))
        if f[0] == "f08.floating_part"
    ]


@pytest.mark.parametrize(
    ("edit", "part"), [(_battery_in_mid_air, "battery_geom"), (_floating_profile, "profile_4040_float")]
)
def test_a_part_in_mid_air_is_refused_with_its_gap(tmp_path, edit, part):
    findings = [msg for code, msg in check_validity(_edited(tmp_path, edit)) if code == "f08.floating_part"]
    assert (
        len(findings) == 1 and f"'{part}'" in findings[0] and " mm from the nearest structure" in findings[0]
    )


def test_f08_cases_with_a_warning_never_pass():
    import dataclasses

    from rle_tasks.f08_mobile_base.batteries import StaticCase

    fine = StaticCase("p", 1, 0.1, 20.0, 0.8, 0.0, 0.1, 0.0)
    assert fine.passed
    assert not dataclasses.replace(fine, warning="simulation warning mjWARN_BADQACC at t = 0.1 s").passed


def test_a_dynamic_scenario_failed_by_a_warning_is_named_in_the_message():
    from rle_tasks.f08_mobile_base.verifier import _scenario_failure

    s = {"scenario": "e_stop", "passed": False, "warning": "simulation warning mjWARN_BADQACC at t = 0.4 s"}
    assert _scenario_failure(s) == "e_stop (simulation warning mjWARN_BADQACC at t = 0.4 s)"
    assert _scenario_failure({**s, "warning": None}) == "e_stop"
