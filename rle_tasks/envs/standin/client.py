"""Stand-in episodes driven by a served policy over the socket protocol (``env="standin"``).

``run_episode`` resets a ``StandinEnv`` to a layout seed and executes the policy's chunks of 14-D
joint targets until the task's goal holds or its horizon passes; a request carries the task's
instruction, the ``head`` and ``front`` views and the 16-D state. Serving is family 05's
(``rle_tasks.envs.libero.client.serving(dir, env="standin")``).
"""

from __future__ import annotations

import numpy as np

from rle_design.policy_socket import PolicyServer, ProtocolError, Request
from rle_tasks.envs.libero.client import EpisodeResult
from rle_tasks.envs.standin.env import StandinEnv

__all__ = ["request", "run_episode"]


def request(obs: dict[str, np.ndarray], instruction: str, episode: int, step: int) -> Request:
    views = np.stack([obs["head"], obs["front"]]).astype(np.uint8)
    return Request(instruction, views, np.asarray(obs["state"], np.float32), episode, step)


def run_episode(
    env: StandinEnv, policy: PolicyServer, seed: int, episode: int = 0, max_steps: int | None = None
) -> EpisodeResult:
    """Reset ``env`` to layout ``seed`` and run ``policy`` until success or ``max_steps`` (default: the
    task's horizon); a protocol fault ends the episode as a failure with its code. ``init_index`` of
    the result is the layout seed."""
    horizon = env.task.max_steps if max_steps is None else int(max_steps)
    obs = env.reset(seed)
    steps = requests = 0
    while steps < horizon:
        try:
            chunk = policy.act(request(obs, env.task.instruction, episode, steps))
        except ProtocolError as exc:
            return EpisodeResult(seed, False, steps, requests, exc.code)
        requests += 1
        for a in chunk:
            success = env.step(a)
            steps += 1
            if success:
                return EpisodeResult(seed, True, steps, requests)
            if steps >= horizon:
                break
        obs = env.observe(views=True)
    return EpisodeResult(seed, False, steps, requests)
