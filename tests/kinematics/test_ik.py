"""IK: Pinocchio chain equals MuJoCo forward kinematics; solutions respect joint limits; residuals."""

import mujoco
import numpy as np
import pytest

from rle_design.errors import MissingElement
from rle_design.kinematics.ik import chain_from_mujoco, solve_ik
from rle_design.scene import arm_ids, compile_spec, compose, element_id

BASE = """<mujoco><worldbody><body name="base" pos="0.3 0.1 0.4" euler="0 0 0.3">
<geom type="box" size="0.2 0.2 0.1" mass="30"/><site name="mount" pos="0 0 0.1"/>
</body></worldbody></mujoco>"""


def _arm(arm: str):
    spec = mujoco.MjSpec.from_string(BASE)
    compose(spec, arm, mount_site="mount")
    m = compile_spec(spec)
    joints = [m.joint(j).name for j in range(m.njnt) if m.joint(j).name.startswith(arm)]
    return m, chain_from_mujoco(m, joints, f"{arm}/tool_site")


@pytest.mark.parametrize("arm", arm_ids())
def test_chain_matches_mujoco_forward_kinematics(arm):
    m, ch = _arm(arm)
    d = mujoco.MjData(m)
    rng = np.random.default_rng(1)
    sid = element_id(m, "site", f"{arm}/tool_site")
    for _ in range(5):
        q = rng.uniform(np.maximum(ch.lower, -2), np.minimum(ch.upper, 2))
        d.qpos[ch.qpos_adr] = q
        mujoco.mj_kinematics(m, d)
        np.testing.assert_allclose(ch.tool(q).translation, ch.to_base(d, d.site_xpos[sid]), atol=1e-9)


@pytest.mark.parametrize("arm", arm_ids())
def test_reachable_target_converges_within_limits(arm):
    _, ch = _arm(arm)
    rng = np.random.default_rng(2)
    q_true = rng.uniform(np.maximum(ch.lower, -1.5), np.minimum(ch.upper, 1.5))
    target = ch.tool(q_true).translation
    r = solve_ik(ch, target, np.clip(np.zeros(len(q_true)), ch.lower, ch.upper))
    assert r.converged and r.position_error < 1e-3
    assert np.all(r.q >= ch.lower - 1e-9) and np.all(r.q <= ch.upper + 1e-9)


def test_unreachable_target_reports_residual_not_exception():
    _, ch = _arm("panda")
    r = solve_ik(ch, np.array([3.0, 0.0, 0.3]), np.zeros(7))
    # The best the arm can do is stretch toward the target: residual >= distance - reach (0.855 m + hand).
    assert not r.converged and r.position_error > 3.0 - 1.2
    assert np.all(r.q >= ch.lower - 1e-9) and np.all(r.q <= ch.upper + 1e-9)


def test_missing_joint_or_site_names_the_alternatives():
    m, _ = _arm("ur5e")
    with pytest.raises(MissingElement) as err:
        chain_from_mujoco(m, ["ur5e/shoulder_pan_joint"], "ur5e/flange")
    assert str(err.value).startswith("site 'ur5e/flange' does not exist. Available sites: mount, ur5e/")
    assert err.value.code == "ik.missing_site"
    with pytest.raises(MissingElement) as err:
        chain_from_mujoco(m, ["ur5e/elbow"], "ur5e/tool_site")
    assert err.value.code == "ik.missing_joint" and "ur5e/elbow_joint" in err.value.available
