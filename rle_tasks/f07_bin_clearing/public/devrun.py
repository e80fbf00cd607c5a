"""Development runner: play a ``policy/`` package on a public pile and print the events.

    python -m bin_clearing.devrun policy --seed 101 [--seconds 120] [--events] [--frames DIR]

The policy runs in this process (no sandbox, no CPU budget), but every value it returns is checked
as the verifier checks it (``contract.py``): a return the evaluation would refuse stops the run with
the evaluation's fault code. The evaluation plays the same episode on hidden piles with the policy
in the sandbox. ``--events`` prints the timeline (floor, damage, impacts, a blocked nest, each
delivery by the nest, each part cleared or arriving around the nest) before the summary;
``--frames`` writes the overhead and wrist cameras as PNG frames at 2 Hz (``PIL`` must be installed).
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
from pathlib import Path

import mujoco

from rle_design.sandbox import ParticipantFault

from .contract import check_return
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


def play(
    package: Path, seed: int, seconds: float = EPISODE_S, frames: Path | None = None, events: bool = False
) -> dict:
    """Events summary of one public pile played by the policy at ``package`` (with ``events``, also
    its ``timeline``: [time s, event, part or -1]).

    Raises:
        ParticipantFault: a return value the verifier would refuse (its code and message).
    """
    pile = PileSpec.public(seed)
    env = make_env(pile)
    model = env.build()
    data = mujoco.MjData(model)
    env.reset(model, data)
    policy = load_policy(package)
    check_return("make_policy", policy.make_policy())
    check_return("reset", policy.reset())
    counter = EventCounter(model, pile.n_parts, control_every=env.n_substeps)
    saved: list[tuple[str, int, object]] = []

    def act(obs: dict):
        tick = int(round(obs["time"] * 10))
        if frames is not None and "overhead" in obs and tick % 5 == 0:
            saved.extend((cam, tick // 5, obs[cam]["rgb"]) for cam in ("overhead", "wrist") if cam in obs)
        return check_return("act", policy.act(obs))

    env.episode(model, data, act, int(round(seconds * 20)), terms=[counter])
    close_cameras(model)
    if frames is not None:
        from PIL import Image

        frames.mkdir(parents=True, exist_ok=True)
        for cam, i, rgb in saved:
            Image.fromarray(rgb).save(frames / f"{cam}_{i:04d}.png")
    out = counter.counts.summary(pile.n_parts, seconds)
    if events:
        out["timeline"] = [[round(t, 2), kind, part] for t, kind, part in counter.counts.timeline]
    return out


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("policy", type=Path, help="the policy/ package")
    ap.add_argument("--seed", type=int, default=101, help="public pile (101-105)")
    ap.add_argument("--seconds", type=float, default=EPISODE_S, help="simulated time [s] (evaluation: 120)")
    ap.add_argument("--events", action="store_true", help="print the event timeline before the summary")
    ap.add_argument("--frames", type=Path, default=None, help="write overhead_*.png and wrist_*.png at 2 Hz")
    a = ap.parse_args(argv)
    try:
        out = play(a.policy, a.seed, a.seconds, a.frames, a.events)
    except ParticipantFault as exc:
        print(f"refused as the evaluation would refuse it: {exc.code}: {exc.message}", file=sys.stderr)
        raise SystemExit(2) from None
    for t, kind, part in out.pop("timeline", []):
        print(f"{t:7.2f} s  {kind:<17} {'' if part < 0 else f'part {part}'}")
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
