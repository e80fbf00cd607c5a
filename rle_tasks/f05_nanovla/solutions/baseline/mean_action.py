"""Baseline recipe: the mean demonstrated action, whatever the observation (a recipe that must fail).

``train`` averages every action of the demonstrations into ``ckpt.pt``; ``serve`` answers every
request with eight copies of it (LIBERO's 7-D actions, or the stand-in's 14 joint targets).
"""

import glob
import os

import numpy as np

from rle_design.policy_socket import serve as _serve


def train(demos_dir: str) -> None:
    actions = [np.load(p)["actions"] for p in sorted(glob.glob(os.path.join(demos_dir, "*.npz")))]
    mean = np.concatenate(actions).mean(axis=0).astype(np.float32)
    with open("ckpt.pt", "wb") as f:
        np.save(f, mean)


def serve(socket_path: str) -> int:
    with open("ckpt.pt", "rb") as f:
        chunk = np.tile(np.load(f), (8, 1))
    env = "standin" if chunk.shape[1] == 14 else "libero"
    return _serve(socket_path, lambda request: chunk, env=env)
