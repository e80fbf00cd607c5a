"""Issue-19 item 9 on 08: every generated addition (a geom on each body, a body under each, a joint of
each type under each) is refused by name at load time (the base's contract names every body, and
geoms other than profiles carry no mass)."""

import shutil

import pytest
from lxml import etree

from rle_design.errors import RleError
from rle_design.mjcf import load_design
from rle_tasks.audit.generated import additions, codes
from rle_tasks.core.solutions import materialise
from rle_tasks.f08_mobile_base.audit import BODIES, expected
from rle_tasks.f08_mobile_base.validity import check_validity


@pytest.fixture(scope="module")
def reference():
    ref = materialise("08-mobile-base", "reference")
    assert check_validity(load_design(ref)) == []
    return ref


@pytest.mark.parametrize("addition", additions(BODIES), ids=lambda a: a.name)
def test_each_addition_is_refused_by_name(reference, tmp_path, addition):
    d = shutil.copytree(reference, tmp_path / "sub")
    tree = etree.parse(str(d / "robot.xml"))
    assert addition.apply(tree.getroot())
    tree.write(str(d / "robot.xml"))
    try:
        problems = check_validity(load_design(d))
    except RleError as exc:  # what the verifier records for a design that does not compile
        problems = [(exc.code, exc.message)]
    want = codes(addition, expected)
    assert set(want) <= {c for c, _ in problems}, problems
    named = ("generated" in m or addition.body in m for c, m in problems if c in want)
    assert any(named), problems
