"""IK: Pinocchio chain equals MuJoCo forward kinematics; solutions respect joint limits; residuals."""

import mujoco
import numpy as np
import pytest

from rle_design.kinematics.ik import chain_from_mujoco, solve_ik
from rle_design.mjcf.compose import compile_spec, compose

BASE = """<mujoco><worldbody><body name="base" pos="0.3 0.1 0.4" euler="0 0 0.3">
<geom type="box" size="0.2 0.2 0.1" mass="30"/><site name="arm_mount_site" pos="0 0 0.1"/>
</body></worldbody></mujoco>"""


def _arm(arm: str):
    spec = mujoco.MjSpec.from_string(BASE)
    compose(spec, arm, None)
    m = compile_spec(spec)
    joints = [m.joint(j).name for j in range(m.njnt) if m.joint(j).name.startswith(arm)]
    return m, chain_from_mujoco(m, joints, f"{arm}/tool_site")


@pytest.mark.parametrize("arm", ["panda", "ur5e", "xarm7"])
def test_chain_matches_mujoco_forward_kinematics(arm):
    m, ch = _arm(arm)
    d = mujoco.MjData(m)
    rng = np.random.default_rng(1)
    sid = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, f"{arm}/tool_site")
    for _ in range(5):
        q = rng.uniform(np.maximum(ch.lower, -2), np.minimum(ch.upper, 2))
        d.qpos[ch.qpos_adr] = q
        mujoco.mj_kinematics(m, d)
        np.testing.assert_allclose(ch.tool(q).translation, ch.to_base(d, d.site_xpos[sid]), atol=1e-9)


@pytest.mark.parametrize("arm", ["panda", "ur5e", "xarm7"])
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
