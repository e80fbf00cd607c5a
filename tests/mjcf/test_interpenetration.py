"""Interpenetration of pairs MuJoCo's contact filter skips: across a joint and welded."""

import mujoco
import numpy as np
import pytest

from rle_design.mjcf.interpenetration import find_overlaps, skipped_pairs

# link A (on a hinge of its own: MuJoCo filters parent/child pairs only away from the world): a 0.1 m
# bar along x ending at a hinge about z at x = 0.1; link B: a bar from the hinge on. An added bracket
# on A reaches ``reach`` m past the hinge, into B's bar when B is straight.
ARM = """<mujoco><worldbody>
  <body name="a" pos="0 0 0.5">
    <joint name="ja" type="hinge" axis="0 1 0"/>
    <geom name="bar_a" type="box" size="0.05 0.01 0.01" pos="0.05 0 0"/>
    <body name="b" pos="0.1 0 0">
      <joint name="j" type="hinge" axis="0 0 1"/>
      <geom name="bar_b" type="box" size="0.05 0.01 0.01" pos="0.06 0 0"/>
    </body>
    <body name="bracket" pos="0 0 0">
      <geom name="post" type="box" size="{half} 0.004 0.004" pos="{centre} 0 0"/>
    </body>
  </body></worldbody></mujoco>"""


def _arm(reach: float) -> mujoco.MjModel:
    # the post runs from x = 0.09 (inside bar A) to 0.1 + 0.01 + reach: B's bar starts at x = 0.11
    start, end = 0.09, 0.11 + reach
    return mujoco.MjModel.from_xml_string(ARM.format(half=(end - start) / 2, centre=(start + end) / 2))


def _ids(m, *names):
    return [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, n) for n in names]


def test_the_filter_skips_exactly_welded_and_parent_child_pairs():
    m = _arm(0.01)
    (bracket,) = _ids(m, "bracket")
    pairs = {(m.geom(g1).name, m.geom(g2).name, across) for g1, g2, across in skipped_pairs(m, [bracket])}
    assert pairs == {("post", "bar_a", False), ("post", "bar_b", True)}


def test_a_part_sunk_into_the_next_link_is_named_with_its_depth():
    m = _arm(0.012)
    (bracket,) = _ids(m, "bracket")
    stock = _ids(m, "a", "b")
    found = find_overlaps(m, [bracket], None, joint_tol=1e-4, weld_tol=np.inf, baseline=stock)
    (o,) = found
    assert (o.geom1, o.body1, o.geom2, o.body2, o.across_joint, o.pose) == (
        "post",
        "bracket",
        "bar_b",
        "b",
        True,
        -1,
    )
    # sunk 12 mm along the bar: the least way out (sideways it is 4 + 10 mm)
    assert o.depth_m == pytest.approx(0.012, abs=1e-6)
    assert o.volume_m3 == pytest.approx(0.012 * 0.008 * 0.008, rel=1e-6)  # 12 x 8 x 8 mm^3 shared
    assert o.message == (
        "part 'post' of body 'bracket' is sunk 12.0 mm into 'bar_b' of body 'b' (across their joint; "
        "768 mm^3 of shared material) at the zero pose"
    )


def test_across_the_grid_the_overlap_follows_the_joint():
    m = _arm(0.015)
    (bracket,) = _ids(m, "bracket")
    poses = np.array([[0.3, 0.0], [0.0, np.pi / 2], [0.0, np.pi], [-0.2, -0.05]])  # (q_a, q_b)
    found = find_overlaps(m, [bracket], poses, joint_tol=1e-4, weld_tol=np.inf, baseline=_ids(m, "a", "b"))
    # B swung away (90 deg, 180 deg): clear; straight or nearly: the post is inside it
    assert sorted({o.pose for o in found}) == [0, 3]


def test_a_part_clear_of_the_next_link_passes():
    m = _arm(-0.005)  # stops 5 mm short of B's bar
    (bracket,) = _ids(m, "bracket")
    assert (
        find_overlaps(m, [bracket], np.array([[0.0, 0.0], [0.0, 0.3]]), joint_tol=1e-4, weld_tol=np.inf) == []
    )


def test_welded_seat_within_its_tolerance_passes_and_deeper_fails():
    m = _arm(-0.005)  # the post is seated 10 mm into bar A (x 0.09 .. 0.1)
    (bracket,) = _ids(m, "bracket")
    assert find_overlaps(m, [bracket], None, joint_tol=1e-4, weld_tol=0.011) == []
    (o,) = find_overlaps(m, [bracket], None, joint_tol=1e-4, weld_tol=0.005)
    assert (o.geom2, o.across_joint) == ("bar_a", False)
    assert o.depth_m == pytest.approx(0.010, abs=1e-6)  # pulled out 10 mm (sideways would be 14 mm)
    assert "(welded to it;" in o.message


def test_what_the_stock_joint_already_shares_is_allowed():
    # stock link B's bar reaches back 10 mm into A's bar; an added part inside that shared region only
    xml = """<mujoco><worldbody><body name="a"><joint type="hinge" axis="0 1 0"/>
      <geom name="bar_a" type="box" size="0.05 0.01 0.01" pos="0.05 0 0"/>
      <body name="b" pos="0.1 0 0"><joint type="hinge" axis="1 0 0"/>
        <geom name="bar_b" type="box" size="0.05 0.01 0.01" pos="0.04 0 0"/></body>
      <body name="plug"><geom name="plug" type="box" size="0.004 0.004 0.004" pos="0.095 0 0"/></body>
    </body></worldbody></mujoco>"""
    m = mujoco.MjModel.from_xml_string(xml)
    plug, a, b = _ids(m, "plug", "a", "b")
    poses = np.array([[0.0, 0.0], [0.4, 0.7]])
    assert find_overlaps(m, [plug], poses, joint_tol=1e-4, weld_tol=np.inf, baseline=[a, b]) == []
    # without the stock baseline the same plug shares material with B
    assert {o.geom2 for o in find_overlaps(m, [plug], poses, joint_tol=1e-4, weld_tol=np.inf)} == {"bar_b"}


def test_a_seat_may_share_a_fraction_of_the_smaller_part():
    m = _arm(-0.005)  # the post (8 x 8 x 15 mm) shares 10 of its 15 mm with bar A: 2/3 of itself
    (bracket,) = _ids(m, "bracket")
    share = 0.010 / 0.015
    assert find_overlaps(m, [bracket], None, joint_tol=1e-4, weld_tol=1e-4, weld_share=share + 0.01) == []
    (o,) = find_overlaps(m, [bracket], None, joint_tol=1e-4, weld_tol=1e-4, weld_share=share - 0.01)
    assert o.volume_m3 == pytest.approx(0.010 * 0.008 * 0.008, rel=1e-6)
