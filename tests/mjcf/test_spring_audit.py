"""Spring build-ability: ends on material, straight paths through no part.

Reference mechanism: a link (capsule of radius R from z = 0 to z = H) on a hinge about +y, pointing
up at q = 0, and a zero-length spring from a world post to a site on the link. A site at distance D
from the capsule's axis is R - D from material when D > R (gap = D - R), and on material otherwise.
"""

import mujoco
import numpy as np
import pytest
from mujoco import MjSpec

from rle_design.mjcf.spring_audit import spring_anchor_faults, spring_path_faults

R, H = 0.02, 0.3
POST = 0.01  # post radius [m]


def _spec(attach_x: float = -R, anchor_on_post: bool = True, wall: bool = False) -> MjSpec:
    spec = MjSpec()
    wb = spec.worldbody
    # A vertical post at x = -0.1 carrying the anchor on its surface (or 5 cm beside it).
    wb.add_geom(name="post", type=mujoco.mjtGeom.mjGEOM_CYLINDER, size=[POST, 0.1, 0], pos=[-0.1, 0, 0.1])
    anchor_x = -0.1 + POST if anchor_on_post else -0.1 + POST + 0.05
    wb.add_site(name="anchor", pos=[anchor_x, 0, 0.15])
    if wall:
        wb.add_geom(
            name="wall", type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.005, 0.05, 0.05], pos=[-0.04, 0, 0.15]
        )
    link = wb.add_body(name="link")
    link.add_joint(name="hinge", type=mujoco.mjtJoint.mjJNT_HINGE, axis=[0, 1, 0])
    link.add_geom(name="shell", type=mujoco.mjtGeom.mjGEOM_CAPSULE, fromto=[0, 0, 0, 0, 0, H], size=[R, 0, 0])
    link.add_site(name="attach", pos=[attach_x, 0, 0.15])
    tendon = spec.add_tendon(name="spring", stiffness=50.0, springlength=[0, 0])
    tendon.wrap_site("anchor")
    tendon.wrap_site("attach")
    return spec


def test_ends_on_material_pass_and_a_floating_end_reports_its_gap():
    assert spring_anchor_faults(_spec()) == []
    faults = spring_anchor_faults(_spec(attach_x=0.07))
    assert [(f.tendon, f.kind, f.element) for f in faults] == [("spring", "anchor", "attach")]
    assert faults[0].value == pytest.approx(0.07 - R, abs=2e-4)  # gap = D - R
    faults = spring_anchor_faults(_spec(anchor_on_post=False))
    assert [f.element for f in faults] == ["anchor"] and faults[0].value == pytest.approx(0.05, abs=2e-4)
    assert "50.0 mm" in faults[0].message


def test_a_bracket_geom_on_the_body_mounts_the_end():
    spec = _spec(attach_x=0.07)
    spec.body("link").add_geom(
        name="bracket", type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.025, 0.005, 0.005], pos=[0.045, 0, 0.15]
    )
    assert spring_anchor_faults(spec) == []


def test_a_clear_path_passes_over_the_workspace():
    m = _spec().compile()  # site on the near side of the link, which tilts away from the post
    assert spring_path_faults(m, np.linspace(0.0, 1.0, 11)[:, None]) == []


def test_a_path_through_a_part_names_the_part_and_the_first_pose():
    m = _spec(wall=True).compile()
    faults = spring_path_faults(m, np.linspace(0.0, 1.0, 11)[:, None])
    assert [(f.kind, f.element, f.pose) for f in faults] == [("path", "wall", 0)]
    # From the anchor (x = -0.09) the path enters the wall at its face x = -0.045: 45 mm.
    assert faults[0].value == pytest.approx(0.045, abs=1e-6)


def _post_spec(site_x: float) -> MjSpec:
    """The link with a printed post from its near side (x = -R) out to x = -0.05, and the spring's
    link end at ``site_x`` on the post's axis."""
    spec = _spec()
    post = spec.body("link").add_body(name="post", pos=[0, 0, 0.15])
    post.add_geom(
        name="post_pla",
        type=mujoco.mjtGeom.mjGEOM_CYLINDER,
        fromto=[-R + 0.002, 0, 0, -0.05, 0, 0],
        size=[0.006, 0, 0],
    )
    post.add_site(name="hook", pos=[site_x, 0, 0])
    tendon = spec.add_tendon(name="post_spring", stiffness=50.0, springlength=[0, 0])
    tendon.wrap_site("anchor")
    tendon.wrap_site("hook")
    spec.tendon("spring").stiffness = [0.0, 0.0, 0.0]  # only the post spring is a spring here
    return spec


def test_a_spring_may_touch_its_own_post_only_near_its_hook():
    # Hooked at the post's tip (x = -0.05): the path from the anchor (x = -0.09) meets the post
    # only at the hook.
    assert spring_path_faults(_post_spec(-0.05).compile(), [[0.0]]) == []
    assert spring_anchor_faults(_post_spec(-0.05)) == []
    # Hooked at the post's root (x = -0.02): the spring runs 30 mm inside its own post, entering it
    # at the tip, 40 mm from the anchor.
    faults = spring_path_faults(_post_spec(-0.02).compile(), [[0.0]])
    assert [(f.tendon, f.element) for f in faults] == [("post_spring", "post_pla")]
    assert faults[0].value == pytest.approx(0.04, abs=1e-6)


def test_a_spring_hooked_on_the_far_side_of_its_own_link_cuts_the_link():
    assert spring_path_faults(_spec(attach_x=-R).compile(), [[0.0]]) == []  # near side: clear
    m = _spec(attach_x=R).compile()  # at q = 0 the site is on the far side: the path crosses the shell
    faults = spring_path_faults(m, [[0.0]])
    assert [(f.element, f.pose) for f in faults] == [("shell", 0)]
    # From the anchor (x = -0.09) the ray enters the shell at x = -R: 0.09 - R = 70 mm.
    assert faults[0].value == pytest.approx(0.09 - R, abs=1e-6)
