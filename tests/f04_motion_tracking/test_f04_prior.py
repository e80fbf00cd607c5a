"""The model-based prior of the family-04 reference: inverse-dynamics feedforward pinned by closed forms,
the feedback structure, and a PPO residual on a TorchScript prior that exports to ONNX unchanged."""

from pathlib import Path

import mujoco
import numpy as np
import pytest

from rle_tasks.f04_motion_tracking.public.clip import Clip, clip_qpos
from rle_tasks.f04_motion_tracking.public.g1 import g1_model
from rle_tasks.f04_motion_tracking.public.g1_constants import G1
from rle_tasks.f04_motion_tracking.solutions.prior import TrackingPrior, feedforward_offsets

CLIP = Path(__file__).resolve().parents[2] / "rle_tasks/f04_motion_tracking/assets/clips/dance.npz"


def _static_clip(model, frame: int, frames: int = 5) -> Clip:
    """The dance clip's frame held still (zero velocities and accelerations)."""
    dance = Clip.load(CLIP)
    qpos = np.repeat(clip_qpos(dance)[frame][None], frames, axis=0)
    return Clip.from_qpos(model, qpos, np.repeat(dance.contacts[frame][None], frames, axis=0))


@pytest.mark.parametrize("joint", ["left_elbow_joint", "right_shoulder_pitch_joint", "waist_pitch_joint"])
def test_feedforward_holds_each_upper_body_joint_against_the_gravity_moment_of_its_subtree(joint):
    """Static pose: tau = -a . ((c - p) x m g) with m and c the mass and COM of everything the joint
    carries, p its anchor and a its axis (the feet's wrenches do not reach the upper body); the offset is
    tau / kp."""
    model = g1_model()
    clip = _static_clip(model, 300)
    offsets = feedforward_offsets(clip, g1_model())
    d = mujoco.MjData(model)
    d.qpos[:] = clip.qpos(2)
    mujoco.mj_forward(model, d)
    j = model.joint(joint).id
    child = model.jnt_bodyid[j]
    mass = model.body_subtreemass[child]
    com = d.subtree_com[child]
    moment = np.cross(com - d.xanchor[j], mass * np.array([0.0, 0.0, -9.81]))
    tau = -float(d.xaxis[j] @ moment)
    k = G1.joints.index(joint)
    kp = model.actuator_gainprm[k, 0]
    assert offsets[2, k] * kp == pytest.approx(tau, abs=1e-6 + 1e-6 * abs(tau))
    assert abs(tau) > 0.05  # a real load, not a trivially zero torque


def test_feedforward_in_single_stance_puts_the_whole_weight_on_the_stance_ankle():
    """Static single stance: the stance ankle roll and pitch torques equal the moment of the whole weight
    about the ankle's axes (the swing foot carries nothing): tau = -a . ((c - p) x M g)."""
    model = g1_model()
    dance = Clip.load(CLIP)
    frame = int(np.flatnonzero(dance.contacts[:, 1] & ~dance.contacts[:, 0])[10])  # right foot alone
    clip = _static_clip(model, frame)
    offsets = feedforward_offsets(clip, g1_model())
    d = mujoco.MjData(model)
    d.qpos[:] = clip.qpos(2)
    mujoco.mj_forward(model, d)
    total = model.body_subtreemass[model.body("pelvis").id]
    com = d.subtree_com[model.body("pelvis").id]
    for name in ("right_ankle_pitch_joint", "right_ankle_roll_joint"):
        j = model.joint(name).id
        # static equilibrium of everything on the body side of the joint (all but its subtree): gravity's
        # moment about the axis is balanced by the reaction of the actuator torque
        below = model.jnt_bodyid[j]
        m_below = model.body_subtreemass[below]
        above_mass = total - m_below
        above_com = (total * com - m_below * d.subtree_com[below]) / above_mass
        moment = np.cross(above_com - d.xanchor[j], above_mass * np.array([0.0, 0.0, -9.81]))
        tau = float(d.xaxis[j] @ moment)
        k = G1.joints.index(name)
        assert offsets[2, k] * model.actuator_gainprm[k, 0] == pytest.approx(tau, abs=1e-5 + 1e-5 * abs(tau))
        assert abs(tau) > 0.1


def test_prior_with_zero_gains_and_zero_feedforward_is_open_loop_replay():
    import torch

    prior = TrackingPrior()
    with torch.no_grad():
        prior.gains.zero_()
        prior.ff[-1].weight.zero_()
        prior.ff[-1].bias.zero_()
    obs = torch.randn(3, 160)
    replay = (obs[:, :29] - torch.tensor(G1.default_pose)) / torch.tensor(G1.action_scale)
    assert torch.allclose(prior(obs), replay, atol=1e-6)


def test_prior_stiffness_gain_multiplies_the_servo_error():
    """legs_stiffness k: target = ref + k (ref - q) on the legs, so the servo's pull is (1 + k) kp."""
    import torch

    prior = TrackingPrior()
    with torch.no_grad():
        prior.gains.zero_()
        prior.gains[16] = 2.0
        prior.ff[-1].weight.zero_()
        prior.ff[-1].bias.zero_()
    obs = torch.zeros(1, 160)
    obs[0, :29] = torch.tensor(G1.default_pose)
    obs[0, 73 + 3] = 0.1  # knee 0.1 rad past its reference
    target = prior(obs)[0] * torch.tensor(G1.action_scale) + torch.tensor(G1.default_pose)
    assert float(target[3] - G1.default_pose[3]) == pytest.approx(-0.2, abs=1e-6)
    assert float(target[15] - G1.default_pose[15]) == pytest.approx(0.0, abs=1e-6)


def test_ppo_residual_on_a_torchscript_prior_exports_to_onnx_unchanged(tmp_path):
    import torch

    from rle_tasks.f04_motion_tracking.evaluation import load_policy
    from rle_tasks.f04_motion_tracking.public.export import export_policy
    from rle_tasks.f04_motion_tracking.public.ppo import ActorCritic

    torch.manual_seed(0)
    prior = TrackingPrior()
    torch.jit.trace(prior.eval(), torch.zeros(1, 160)).save(str(tmp_path / "prior.pt"))
    batch = torch.randn(5, 160)
    with torch.no_grad():  # the traced prior runs any batch size (PPO's minibatches)
        assert torch.allclose(torch.jit.load(str(tmp_path / "prior.pt"))(batch), prior(batch), atol=1e-6)
    net = ActorCritic(prior=torch.jit.load(str(tmp_path / "prior.pt")))
    assert all(not p.requires_grad for p in net.prior.parameters())
    x = torch.randn(1, 160)
    with torch.no_grad():
        assert torch.allclose(net.mean_action(x), prior(x) + net.actor(net.normalise(x)), atol=1e-6)
    export_policy(net, tmp_path / "sub")
    _, policy = load_policy(tmp_path / "sub")
    xs = np.random.default_rng(0).normal(size=(1, 160)).astype(np.float32)
    with torch.no_grad():
        expected = net(torch.as_tensor(xs)).numpy()[0]
    assert policy.run({"obs": xs})["actions"][0] == pytest.approx(expected, abs=1e-4)
