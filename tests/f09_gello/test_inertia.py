"""Issue-19 regression on 09: "easy to move" includes inertia.

Backdrive used to measure breakaway torque only, so steel that improves holding or push recovery was
free. The backdrive checkpoints now add the torque to accelerate the joint inertia a design adds over
the stock leader at ``ACCEL_REF``; pinned here on closed forms.
"""

import shutil

import mujoco
import numpy as np
import pytest
from lxml import etree

from rle_tasks.core.registry import get_task
from rle_tasks.core.runtime.secrets import PUBLIC_KEY, Secret
from rle_tasks.core.solutions import materialise
from rle_tasks.core.task import VerifyContext
from rle_tasks.core.verify import run_verify
from rle_tasks.f09_gello import battery
from rle_tasks.f09_gello.device import ASSET_DIR, STEEL_DENSITY, stock_model
from rle_tasks.f09_gello.public.gello_helpers import workspace_grid

TASK = get_task("09-gello")
R, RHO = 0.15, 0.015  # sphere distance from the joint-1 axis and sphere radius [m]
M_S = STEEL_DENSITY * 4 / 3 * np.pi * RHO**3  # 0.111 kg
BAR = (R, 0.006, 0.006)  # PLA bar half-sizes [m]
M_B = 1240.0 * 8 * BAR[0] * BAR[1] * BAR[2]
# about joint 1 (link1's z axis): two spheres m (r^2 + 2/5 rho^2) + a box m ((2a)^2 + (2b)^2) / 12
DUMBBELL_I = 2 * M_S * (R**2 + 0.4 * RHO**2) + M_B * ((2 * BAR[0]) ** 2 + (2 * BAR[1]) ** 2) / 12


def _dumbbell(root) -> None:
    """A printed bar through link1's shell with a steel sphere at each end: no gravity torque on any
    joint (joint 1 is vertical, the masses ride on link1), only inertia about joint 1."""
    link1 = next(b for b in root.iter("body") if b.get("name") == "link1")
    body = etree.SubElement(link1, "body", name="dumbbell", pos="0 0 0.07")
    etree.SubElement(
        body, "geom", name="dumbbell_bar", type="box", size=" ".join(map(str, BAR)), density="1240"
    )
    for side in (1, -1):
        etree.SubElement(
            body, "geom", type="sphere", size=str(RHO), pos=f"{side * R} 0 0", density=str(STEEL_DENSITY)
        )


def test_added_inertia_is_the_closed_form():
    spec = mujoco.MjSpec.from_file(str(ASSET_DIR / "panda" / "lead.xml"))
    body = spec.body("link1").add_body(name="weight", pos=[R, 0.0, 0.07])
    body.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[RHO, 0, 0], density=STEEL_DENSITY)
    m = spec.compile()
    stock = stock_model("panda")
    poses = workspace_grid(stock.jnt_range, 8, seed=3)
    added = battery.added_inertia(m, stock, poses)
    assert added[:, 0] == pytest.approx(M_S * (R**2 + 0.4 * RHO**2), rel=1e-9)  # parallel axes
    assert np.all(added[:, 1:] < 1e-15)  # the weight rides on link1: no joint beyond carries it
    assert np.all(battery.added_inertia(stock, stock, poses) == 0.0)


def test_a_heavy_design_pays_in_backdrive(tmp_path):
    ctx = VerifyContext(secret=Secret(PUBLIC_KEY, public=True), quick=True)
    ref_dir = materialise(TASK, "reference")
    heavy = shutil.copytree(ref_dir, tmp_path / "heavy")
    path = heavy / "panda" / "lead.xml"
    tree = etree.parse(str(path))
    _dumbbell(tree.getroot())
    tree.write(str(path))
    ref, _ = run_verify(TASK, ref_dir, ctx)
    rep, internal = run_verify(TASK, heavy, ctx)
    assert not internal and not [e for e in rep.errors if e.code.startswith("contract.")]
    before, after = ref.native_metrics["panda"], rep.native_metrics["panda"]
    # the dumbbell adds no gravity torque: the passive residual is unchanged
    assert after["residual_p95_Nm"] == pytest.approx(before["residual_p95_Nm"], abs=1e-9)
    # it adds DUMBBELL_I (0.0056 kg m^2) about joint 1: 3 rad/s^2 x that on top of what the reference adds
    extra = np.asarray(after["added_inertia_kgm2"]) - np.asarray(before["added_inertia_kgm2"])
    assert extra[0] == pytest.approx(DUMBBELL_I, rel=1e-6) and np.allclose(extra[1:], 0.0, atol=1e-12)
    assert min(after["inertia_effort_Nm"]) >= battery.ACCEL_REF * DUMBBELL_I
    for key in ("passive_backdrive_Nm", "combined_backdrive_Nm"):
        assert min(after[key]) >= battery.ACCEL_REF * DUMBBELL_I
        # same poses, same gravity: the measurement can only grow
        assert all(a >= b - 1e-12 for a, b in zip(after[key], before[key], strict=True))


def test_backdrive_scores_breakaway_plus_effort_on_the_worst_joint():
    """``_hold_back_push`` adds the effort per joint before taking the worst joint: an effort of
    0.2 N m on joint 1 of the balanced stock leader at rest (breakaway = servo friction 0.0128 N m)
    reads 0.2128 N m."""
    from rle_tasks.f09_gello.measurements import _hold_back_push

    m = stock_model("panda")
    q = np.array([[0.0, 0.0, 0.0, -1.5, 0.0, 1.5, 0.0]])
    ff = battery.residual_mujoco(m, q)  # an exact feedforward: no net torque, breakaway = friction
    effort = np.zeros((1, m.nv))
    plain = _hold_back_push(m, q, ff, np.zeros_like(ff), 0.1, None, [])
    effort[0, 0] = 0.2
    paid = _hold_back_push(m, q, ff, np.zeros_like(ff), 0.1, None, [], effort)
    friction = float(m.dof_frictionloss[0])
    assert plain["backdrive"][0] == pytest.approx(friction, rel=0.05)
    assert paid["backdrive"][0] == pytest.approx(0.2 + friction, rel=0.02)
