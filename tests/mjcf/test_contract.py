"""Contract findings: each forbidden construct has its own code, and the message names element and line."""

from pathlib import Path

import pytest

from rle_design.errors import MjcfError
from rle_design.mjcf.contract import Finding, ModelContract, check_contract
from rle_design.mjcf.loader import load_design

FIXTURES = Path(__file__).resolve().parents[1] / "fixtures" / "mjcf"

PASSIVE = ModelContract(
    required={"site": ("tip",), "joint": ("j1",), "body": ("link1",)},
    forbid_gravcomp=True,
    forbid_option_changes=True,
    allowed_options=("timestep",),
    forbid_world_welds=True,
    forbid_actuators=True,
    forbid_multiple_roots=True,
    forbid_massless_bodies=True,
    forbid_frames=True,
)


def test_good_passive_device_has_no_findings():
    assert check_contract(load_design(FIXTURES / "passive_lead_good"), PASSIVE) == []


def test_every_forbidden_construct_gets_its_code_name_and_line():
    findings = check_contract(load_design(FIXTURES / "passive_lead_bad"), PASSIVE)
    assert findings == [
        Finding(
            "contract.gravcomp",
            "body 'link1' (line 7) sets gravcomp=\"1\"; gravity compensation by fiat is forbidden",
            "body",
            7,
            "robot.xml",
        ),
        Finding(
            "contract.option_changed",
            "<option> gravity (line 3) changed from 0 0 -9.81 (default) to 0 0 -5; allowed changes: timestep",
            "option",
            3,
            "robot.xml",
        ),
        Finding(
            "contract.world_weld",
            "weld 'hold' (line 24) ties body 'link1' to the world (body2 omitted); "
            "welds/connects to the world are forbidden",
            "weld",
            24,
            "robot.xml",
        ),
        Finding(
            "contract.actuator",
            "actuator <motor> 'm1' (line 27) is forbidden: the device must be passive",
            "motor",
            27,
            "robot.xml",
        ),
        Finding(
            "contract.multiple_roots",
            "body 'extra' (line 19) is root body 2 under <worldbody>; exactly one is allowed (roots: base, extra)",
            "body",
            19,
            "robot.xml",
        ),
        Finding(
            "contract.massless_body",
            "body 'ghost' (line 12) has mass 0 kg; every body needs mass",
            "body",
            12,
            "robot.xml",
        ),
        Finding(
            "contract.frame",
            "body 'in_frame' (line 14) is inside <frame> 'bracket'; Pinocchio drops such bodies",
            "body",
            14,
            "robot.xml",
        ),
    ]


def test_flags_are_off_by_default_except_the_inertia_check():
    off = ModelContract(forbid_invalid_inertia=False)
    assert check_contract(load_design(FIXTURES / "passive_lead_bad"), off) == []


def test_missing_required_names_list_the_available_ones():
    contract = ModelContract(required={"site": ("arm_mount_site",), "actuator": ("drive",)})
    findings = check_contract(load_design(FIXTURES / "passive_lead_good"), contract)
    assert [(f.code, f.message) for f in findings] == [
        ("contract.missing_actuator", "actuator 'drive' does not exist. Available actuators: (none)"),
        ("contract.missing_site", "site 'arm_mount_site' does not exist. Available sites: tip"),
    ]
    with pytest.raises(MjcfError) as info:
        check_contract(load_design(FIXTURES / "passive_lead_good"), ModelContract(required={"wheel": ("w",)}))
    assert "contract kind 'wheel' does not exist" in str(info.value)


BODY = '<body name="arm"><joint name="j" axis="0 1 0"/><geom size=".05" density="1000"/>{}</body>'


@pytest.mark.parametrize(
    ("extra", "expected"),
    [
        (
            '<equality><weld name="w" body1="world" body2="arm"/></equality>',
            "weld 'w' (line 2) ties body 'arm' to the world; welds/connects to the world are forbidden",
        ),
        (
            '<equality><connect body1="arm" anchor="0 0 0"/></equality>',
            "connect 'unnamed' (line 2) ties body 'arm' to the world (body2 omitted); "
            "welds/connects to the world are forbidden",
        ),
        (
            '<equality><weld site1="s_arm" site2="s_world"/></equality>',
            "weld 'unnamed' (line 2) ties site 's_world' on the world body; welds/connects to the world are forbidden",
        ),
    ],
)
def test_world_weld_variants(artifact, extra, expected):
    xml = (
        '<mujoco><worldbody><site name="s_world"/>'
        + BODY.format('<site name="s_arm"/>')
        + "</worldbody>\n"
        + extra
        + "</mujoco>"
    )
    findings = check_contract(
        load_design(artifact({"robot.xml": xml})), ModelContract(forbid_world_welds=True)
    )
    assert [(f.code, f.message) for f in findings] == [("contract.world_weld", expected)]


def test_weld_between_two_bodies_is_allowed(artifact):
    xml = (
        "<mujoco><worldbody>"
        + BODY.format('<body name="b"><joint axis="1 0 0"/><geom size=".02"/></body>')
        + '</worldbody><equality><weld body1="arm" body2="b"/></equality></mujoco>'
    )
    assert (
        check_contract(load_design(artifact({"robot.xml": xml})), ModelContract(forbid_world_welds=True))
        == []
    )


def test_actuator_gravcomp_and_flags(artifact):
    xml = (
        '<mujoco>\n<option><flag gravity="disable"/></option>\n<worldbody>\n'
        '<body name="arm"><joint name="j" axis="0 1 0" actuatorgravcomp="true"/><geom size=".05"/></body>'
        "\n</worldbody></mujoco>"
    )
    design = load_design(artifact({"robot.xml": xml}))
    findings = check_contract(design, ModelContract(forbid_gravcomp=True, forbid_option_changes=True))
    assert [(f.code, f.element, f.line) for f in findings] == [
        ("contract.gravcomp", "joint", 4),
        ("contract.option_changed", "flag", 2),
    ]
    assert findings[0].message == (
        "joint 'j' (line 4) sets actuatorgravcomp=\"true\"; gravity compensation by fiat is forbidden"
    )
    assert (
        findings[1].message
        == "<flag> gravity (line 2) changed from enable (default) to disable; allowed changes: (none)"
    )
    allowed = ModelContract(forbid_option_changes=True, allowed_options=("flag.gravity",))
    assert check_contract(design, allowed) == []


def test_included_file_findings_name_that_file(artifact):
    root = artifact(
        {
            "robot.xml": "<mujoco><worldbody><include file='parts/arm.xml'/></worldbody></mujoco>",
            "parts/arm.xml": '<mujoco>\n<body name="arm" gravcomp="0.5"><geom size=".05"/></body>\n</mujoco>',
        }
    )
    (finding,) = check_contract(load_design(root), ModelContract(forbid_gravcomp=True))
    assert (finding.code, finding.path, finding.line) == ("contract.gravcomp", "parts/arm.xml", 2)


def test_massless_check_reports_compile_failure(artifact):
    xml = '<mujoco><worldbody><body><joint/><geom type="mesh" mesh="nope"/></body></worldbody></mujoco>'
    (finding,) = check_contract(
        load_design(artifact({"robot.xml": xml})), ModelContract(forbid_massless_bodies=True)
    )
    assert finding.code == "mjcf.compile" and "mesh 'nope' not found" in finding.message


@pytest.mark.parametrize(
    "inertial, moments",
    [
        ('diaginertia="-1 1 1"', "-1, 1, 1"),  # MuJoCo clamps the negative moment silently
        ('diaginertia="1 1 3"', "1, 1, 3"),  # 3 > 1 + 1: no rigid body has this inertia
        ('fullinertia="1 1 1 2 0 0"', "-1, 1, 3"),  # eigenvalues of [[1,2,0],[2,1,0],[0,0,1]]
    ],
)
def test_unphysical_inertia_is_rejected_with_its_moments(artifact, inertial, moments):
    xml = (
        "<mujoco><worldbody><body name='link'><joint axis='0 1 0'/><geom size='.02'/>"
        f"<body name='ballast'><inertial pos='0 0 0' mass='0.1' {inertial}/></body>"
        "</body></worldbody></mujoco>"
    )
    findings = check_contract(load_design(artifact({"robot.xml": xml})), ModelContract())
    assert [f.code for f in findings] == ["contract.invalid_inertia"]
    assert (
        f"<inertial> of body 'ballast' (line 1) has principal moments {moments} kg m^2" in findings[0].message
    )


def test_negative_geom_mass_is_rejected(artifact):
    xml = "<mujoco><worldbody><body name='b'><joint/><geom name='g' size='.02' mass='-2'/></body></worldbody></mujoco>"
    findings = check_contract(load_design(artifact({"robot.xml": xml})), ModelContract())
    assert "contract.invalid_inertia" in [f.code for f in findings]


def test_valid_inertia_passes(artifact):
    # a uniform rod of mass m, length L about its centre: I = (m L^2/12, m L^2/12, ~0) is physical
    xml = (
        "<mujoco><worldbody><body name='b'><joint/><geom size='.02'/>"
        "<body name='rod'><inertial pos='0 0 0' mass='1.2' diaginertia='0.1 0.1 1e-6'/></body>"
        "</body></worldbody></mujoco>"
    )
    assert check_contract(load_design(artifact({"robot.xml": xml})), ModelContract()) == []
