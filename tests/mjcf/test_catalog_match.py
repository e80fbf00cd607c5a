"""Profile geoms against catalogs/profiles.yaml: section, length x kg/m mass, cost, unknown ids."""

from pathlib import Path

import pytest
from lxml import etree

from rle_design.mjcf.catalog_match import match_profiles
from rle_design.mjcf.contract import Finding
from rle_design.mjcf.loader import load_design

FIXTURE = Path(__file__).resolve().parents[1] / "fixtures" / "mjcf" / "profile_frame"


@pytest.fixture(scope="module")
def report():
    design = load_design(FIXTURE)
    return match_profiles(design, design.compile())


def test_mass_mismatch_carries_both_numbers(report):
    # expected mass = length x linear mass = 0.600 m x 1.740 kg/m = 1.044 kg; declared 2.5 kg
    assert report.findings[0] == Finding(
        "catalog.mass_mismatch",
        "geom 'profile_4040_left_rail': mass 2.500 kg != length 0.600 m x 1.740 kg/m = 1.044 kg",
        "geom",
        6,
        "robot.xml",
    )


def test_other_findings(report):
    assert [(f.code, f.line, f.message) for f in report.findings[1:]] == [
        (
            "catalog.unknown_profile",
            10,
            "geom 'profile_5050_beam': profile '5050' is not in the catalog. "
            "Available profiles: 2020, 2040, 3030, 4040, 4080",
        ),
        (
            "catalog.section_mismatch",
            11,
            "geom 'profile_3030_brace': section 30.0 x 40.0 mm != profile 3030 30.0 x 30.0 mm (tolerance 0.5 mm)",
        ),
        (
            "catalog.missing_mass",
            12,
            "geom 'profile_2020_nomass': a profile must declare mass=\"0.100\" (kg)",
        ),
    ]
    assert not report.ok


def test_lengths_masses_costs(report):
    by_name = {p.geom: p for p in report.profiles}
    assert "deck" not in by_name and "profile_5050_beam" not in by_name
    # rotated rail (euler) and fromto post: the largest full size is the length, either section order
    right = by_name["profile_4040_right_rail"]
    assert (right.profile_id, right.length, right.declared_mass) == ("4040", pytest.approx(0.6), 1.044)
    post = by_name["profile_2020_post"]
    assert post.length == pytest.approx(0.5) and post.expected_mass == pytest.approx(0.5 * 0.5)
    assert by_name["profile_2040_cross"].expected_mass == pytest.approx(0.4 * 0.84)
    # totals: sum of lengths; mass and cost from the catalog (kg/m, EUR/m)
    lengths = {"4040": 1.2, "2040": 0.4, "2020": 0.7, "3030": 0.2}
    kg_per_m = {"4040": 1.74, "2040": 0.84, "2020": 0.50, "3030": 0.90}
    eur_per_m = {"4040": 13.29, "2040": 6.90, "2020": 3.95, "3030": 7.81}
    assert report.total_length == pytest.approx(sum(lengths.values()))
    assert report.total_mass == pytest.approx(sum(lengths[k] * kg_per_m[k] for k in lengths))
    assert report.total_cost == pytest.approx(sum(lengths[k] * eur_per_m[k] for k in lengths))


def test_within_two_percent_passes_and_tree_input_works(artifact):
    xml = (
        '<mujoco><worldbody><body><geom name="profile_2020_a" type="box" size="0.01 0.01 0.5" mass="0.509"/>'
        '<geom name="profile_2020_b" type="box" size="0.01 0.01 0.5" mass="0.511"/></body></worldbody></mujoco>'
    )
    design = load_design(artifact({"robot.xml": xml}))
    rep = match_profiles(design.tree, design.compile())
    # 1.0 m x 0.5 kg/m = 0.5 kg: 0.509 is within 2 %, 0.511 is not
    assert [(f.code, f.path, f.line) for f in rep.findings] == [("catalog.mass_mismatch", None, 1)]
    assert (
        rep.findings[0].message
        == "geom 'profile_2020_b': mass 0.511 kg != length 1.000 m x 0.500 kg/m = 0.500 kg"
    )
    assert match_profiles(etree.fromstring(xml), design.compile()).findings == rep.findings


def test_profile_must_be_a_box(artifact):
    xml = '<mujoco><worldbody><body><geom name="profile_2020_rod" type="cylinder" size="0.01 0.5" mass="0.5"/></body></worldbody></mujoco>'
    design = load_design(artifact({"robot.xml": xml}))
    (finding,) = match_profiles(design, design.compile()).findings
    assert (finding.code, finding.message) == (
        "catalog.not_a_box",
        "geom 'profile_2020_rod': a profile must be a box geom",
    )
