"""Issue-19 item 9 on 09: every generated addition (a geom on each stock body, a body under each, a
joint of each type under each) is either accounted for or refused by name, and none reaches the
verifier's physics as a shape error."""

import shutil

import pytest
from lxml import etree

from rle_tasks.audit.generated import additions, codes
from rle_tasks.core.registry import get_task
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.core.solutions import materialise
from rle_tasks.core.task import VerifyContext
from rle_tasks.core.verify import run_verify
from rle_tasks.f09_gello.audit import BODIES, expected
from rle_tasks.f09_gello.submission import load_submission

TASK = get_task("09-gello")
ADDITIONS = additions(BODIES)


@pytest.fixture(scope="module")
def reference():
    ref = materialise(TASK, "reference")
    return ref, load_submission("panda", ref / "panda")


@pytest.mark.parametrize("addition", ADDITIONS, ids=lambda a: a.name)
def test_each_addition_is_accounted_or_refused_by_name(reference, tmp_path, addition):
    ref, ref_sub = reference
    d = shutil.copytree(ref / "panda", tmp_path / "panda")
    tree = etree.parse(str(d / "lead.xml"))
    assert addition.apply(tree.getroot())
    tree.write(str(d / "lead.xml"))
    sub = load_submission("panda", d)
    want = codes(addition, expected)
    found = {f.code for f in sub.structure}
    if want:
        assert set(want) <= found, [f"{f.code}: {f.message}" for f in sub.structure]
        assert not sub.usable
        body = "link7" if addition.body == "tip" else addition.body
        assert any(("generated" in f.message) or (body in f.message) for f in sub.structure)
    else:  # a welded PLA part: allowed, and its mass is the device's
        assert not found, [f"{f.code}: {f.message}" for f in sub.structure]
        added = sub.model.body("generated_body").mass[0]
        assert added == pytest.approx(1240.0 * 4 / 3 * 3.141592653589793 * 0.01**3, rel=1e-9)
        assert sub.mass == pytest.approx(ref_sub.mass + added, abs=1e-12)


def test_a_refused_addition_on_every_leader_verifies_without_a_fault(tmp_path):
    d = shutil.copytree(materialise(TASK, "reference"), tmp_path / "sub")
    a = next(x for x in ADDITIONS if x.name == "ball_joint_under_link2")
    for robot in ("panda", "ur5e", "xarm7"):
        path = d / robot / "lead.xml"
        tree = etree.parse(str(path))
        a.apply(tree.getroot())
        tree.write(str(path))
    report, internal = run_verify(TASK, d, VerifyContext(secret=Secret(PUBLIC_KEY, public=True), quick=True))
    assert not internal and "contract.extra_joint" in {e.code for e in report.errors}
    assert report.score <= 0.2
