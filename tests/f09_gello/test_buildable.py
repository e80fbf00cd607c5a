"""Issue-19 regressions on 09: parts that must be fastened, springs that must be mounted and clear.

The old reference hung its steel counterweights in mid-air (21-104 mm from their links) and hooked
its shoulder spring to bare sites up to 50 mm from any material; the rebuilt reference fastens each
counterweight on a printed PLA rod and each spring end on a printed post. Each edit below turns the
reference back into something that could not be built, and is refused for its named reason.
"""

import shutil

import mujoco
import numpy as np
import pytest
from lxml import etree

from rle_design.catalog import load_catalog
from rle_tasks.core.registry import get_task
from rle_tasks.core.solutions import materialise
from rle_tasks.f09_gello.buildable import SPRING_CUT_MAX, spring_cut_poses
from rle_tasks.f09_gello.leaders import ROBOTS
from rle_tasks.f09_gello.public.gello_helpers import PUBLIC_GRID_SIZE, workspace_grid
from rle_tasks.f09_gello.submission import load_submission, springs_summary

TASK = get_task("09-gello")


@pytest.fixture(scope="module")
def reference():
    return materialise(TASK, "reference")


@pytest.mark.parametrize("robot", ROBOTS)
def test_the_reference_is_buildable(reference, robot):
    sub = load_submission(robot, reference / robot)
    assert not sub.structure, [f.message for f in sub.structure]
    m = sub.model
    names = [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, b) for b in sub.added_bodies]
    assert any(n.startswith("counterweight") for n in names) and "spring_anchor_post" in names
    # the shoulder spring is a catalog part, and its mass is part of the device's
    (spring,) = springs_summary(m)
    entry = load_catalog("springs").get(spring["catalog"])
    assert sub.mass == pytest.approx(m.body_mass[1:].sum() + entry.mass)
    # every added body carries at least solid PLA of its volume (steel spheres on PLA rods)
    for b in sub.added_bodies:
        assert m.body_mass[b] > 0.0
    grid = workspace_grid(m.jnt_range, PUBLIC_GRID_SIZE)
    assert len(spring_cut_poses(m, grid)) <= SPRING_CUT_MAX * len(grid)


def _edited(reference, tmp_path, robot, edit):
    out = tmp_path / robot
    shutil.copytree(reference / robot, out)
    path = out / "lead.xml"
    tree = etree.parse(str(path))
    edit(tree.getroot())
    tree.write(str(path))
    return load_submission(robot, out)


def _by_name(root, tag, name):
    return next(e for e in root.iter(tag) if e.get("name") == name)


def _drop_rod(root):
    rod = _by_name(root, "geom", "counterweight1_rod")
    rod.getparent().remove(rod)


def _lift_spring_end(root):
    _by_name(root, "site", "spring_anchor").set("pos", "0.08 0.08 0.08")


def _spring_through_arm(root):
    # a catalog spring on a slack cable (never loaded), so only its path is at fault
    tendon = etree.SubElement(root, "tendon")
    sp = etree.SubElement(tendon, "spatial", name="long_spring", stiffness="717.05", springlength="0 2")
    etree.SubElement(sp, "site", site="mount_site")
    etree.SubElement(sp, "site", site="handle_site")


def _ideal_spring(root):
    """The exact (optimiser's) stiffness instead of the catalog spring: no part has that rate."""
    _by_name(root, "spatial", "shoulder_spring").set("stiffness", "950")


def _weak_spring(root):
    """A catalog spring rated 56.2 N (cs-d1.6-D12-n40, 939.852 N/m) where the shoulder pulls ~70 N."""
    _by_name(root, "spatial", "shoulder_spring").set("stiffness", "939.852")


def _pushing_spring(root):
    """A 30 mm spring length: at folded poses the tendon is shorter and MuJoCo's spring would push."""
    _by_name(root, "spatial", "shoulder_spring").set("springlength", "0.03")


def _ideal_torsion_spring(root):
    _by_name(root, "joint", "j2").set("stiffness", "0.5")


def _weightless_strut(root):
    link = _by_name(root, "body", "link3")
    strut = etree.SubElement(link, "body", name="strut")
    etree.SubElement(strut, "geom", type="box", size="0.03 0.01 0.01", mass="0.0001")


@pytest.mark.parametrize(
    "edit, code, words",
    [
        (_drop_rod, "contract.floating_part", "counterweight1"),
        (_lift_spring_end, "contract.spring_anchor", "spring_anchor"),
        (_spring_through_arm, "contract.spring_path", "long_spring"),
        (_weightless_strut, "contract.underweight_part", "strut"),
        (_ideal_spring, "contract.spring_catalog", "stiffness 950 N/m is no catalog spring"),
        (_weak_spring, "contract.spring_overload", "exceeds its 56.2 N rating"),
        (_pushing_spring, "contract.spring_push", "a cable only pulls"),
        (_ideal_torsion_spring, "contract.spring_catalog", "joint 'j2': stiffness 0.5 is no torsion"),
    ],
)
def test_what_could_not_be_built_is_refused_by_name(reference, tmp_path, edit, code, words):
    sub = _edited(reference, tmp_path, "panda", edit)
    found = [f for f in sub.structure if f.code == code]
    assert found and words in found[0].message, [f"{f.code}: {f.message}" for f in sub.structure]
    if code == "contract.underweight_part":
        # 1e-4 kg for a 60 x 20 x 20 mm box: 24 cm^3, 4.17 kg/m^3, lighter than PLA's 1240 kg/m^3
        assert "0.0001 kg in 24 cm^3 (4.16667 kg/m^3)" in found[0].message
        assert "pla 1240-1250" in found[0].message


def test_a_floating_counterweight_reports_its_gap_in_mm(reference, tmp_path):
    sub = _edited(reference, tmp_path, "panda", _drop_rod)
    msg = next(f.message for f in sub.structure if f.code == "contract.floating_part")
    gap_mm = float(msg.split(": ")[1].split(" mm")[0])
    steel = sub.model.geom("counterweight1_steel").id
    assert gap_mm > 1.0 and np.isfinite(gap_mm) and steel >= 0
