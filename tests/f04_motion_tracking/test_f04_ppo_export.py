"""PPO trainer smoke run and the exporter: the exported graph meets the contract and equals torch."""

from pathlib import Path

import numpy as np
import pytest

from rle_tasks.f04_motion_tracking.evaluation import count_parameters, load_policy
from rle_tasks.f04_motion_tracking.public.export import export_policy
from rle_tasks.f04_motion_tracking.public.ppo import ActorCritic, train

CLIP = Path(__file__).resolve().parents[2] / "rle_tasks/f04_motion_tracking/assets/clips/dance.npz"


def test_untrained_actor_is_open_loop_replay():
    """The residual starts at 1 % scale: the mean action is (ref - default) / scale up to that residual."""
    import torch

    from rle_tasks.f04_motion_tracking.public.g1_constants import G1

    torch.manual_seed(0)
    net = ActorCritic()
    obs = torch.zeros(1, 160)
    obs[0, :29] = torch.tensor(G1.default_pose) + 0.1
    replay = 0.1 / torch.tensor(G1.action_scale)
    assert torch.allclose(net.mean_action(obs), replay, atol=0.05)


@pytest.mark.physics
def test_ppo_runs_and_its_export_meets_the_contract(tmp_path):
    import torch

    net = train(CLIP, tmp_path / "run", minutes=0.05, num_envs=2, horizon=8)
    rows = (tmp_path / "run" / "curve.csv").read_text().splitlines()
    assert rows[0].startswith("iteration") and len(rows) >= 2
    export_policy(net, tmp_path / "sub")
    meta, policy = load_policy(tmp_path / "sub")
    assert meta.history == 1 and 50_000 < count_parameters(tmp_path / "sub") < 200_000
    x = np.random.default_rng(0).normal(size=(1, 160)).astype(np.float32)
    with torch.no_grad():
        expected = net(torch.as_tensor(x)).numpy()[0]
    assert policy.run({"obs": x})["actions"][0] == pytest.approx(expected, abs=1e-4)


def test_smoothing_is_a_first_order_filter_on_the_previous_action(tmp_path):
    """alpha = 0.3: a = 0.3 net(obs) + 0.7 obs[131:160] (the previous action of the observation)."""
    import torch

    torch.manual_seed(1)
    net = ActorCritic()
    export_policy(net, tmp_path, smoothing=0.3)
    _, policy = load_policy(tmp_path)
    x = np.random.default_rng(2).normal(size=(1, 160)).astype(np.float32)
    with torch.no_grad():
        expected = 0.3 * net(torch.as_tensor(x)).numpy()[0] + 0.7 * x[0, 131:160]
    assert policy.run({"obs": x})["actions"][0] == pytest.approx(expected, abs=1e-4)
