"""Development runner: play a ``policy/`` package on a public pile and print the events.

    python -m bin_clearing.devrun policy --seed 101 [--seconds 120] [--frames DIR]

The policy runs in this process (no sandbox, no CPU budget); the evaluation runs the same episode on
hidden piles with the policy in the sandbox. ``--frames`` writes the overhead camera as PNG frames at
2 Hz (``imageio`` or ``PIL`` must be installed).
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
from pathlib import Path

import mujoco

from .env import EPISODE_S, close_cameras, make_env
from .events import EventCounter
from .pile import PileSpec


def load_policy(package: Path):
    """Import ``package/__init__.py`` as module ``policy``."""
    init = Path(package) / "__init__.py"
    spec = importlib.util.spec_from_file_location("policy", init, submodule_search_locations=[str(package)])
    module = importlib.util.module_from_spec(spec)
    sys.modules["policy"] = module
    spec.loader.exec_module(module)
    return module


def play(package: Path, seed: int, seconds: float = EPISODE_S, frames: Path | None = None) -> dict:
    """Events summary of one public pile played by the policy at ``package``."""
    pile = PileSpec.public(seed)
    env = make_env(pile)
    model = env.build()
    data = mujoco.MjData(model)
    env.reset(model, data)
    policy = load_policy(package)
    policy.make_policy()
    policy.reset()
    counter = EventCounter(model, pile.n_parts, control_every=env.n_substeps)
    saved = []

    def act(obs: dict):
        if frames is not None and "overhead" in obs and int(round(obs["time"] * 10)) % 5 == 0:
            saved.append(obs["overhead"]["rgb"])
        return policy.act(obs)

    env.episode(model, data, act, int(round(seconds * 20)), terms=[counter])
    close_cameras(model)
    if frames is not None:
        from PIL import Image

        frames.mkdir(parents=True, exist_ok=True)
        for i, rgb in enumerate(saved):
            Image.fromarray(rgb).save(frames / f"frame_{i:04d}.png")
    return counter.counts.summary(pile.n_parts, seconds)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("policy", type=Path)
    ap.add_argument("--seed", type=int, default=101)
    ap.add_argument("--seconds", type=float, default=EPISODE_S)
    ap.add_argument("--frames", type=Path, default=None)
    a = ap.parse_args(argv)
    print(json.dumps(play(a.policy, a.seed, a.seconds, a.frames), indent=1))


if __name__ == "__main__":
    main()
