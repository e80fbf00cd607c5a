"""Baseline recipe that must fail: trains like the mean-action recipe, then serves NaN actions.

It speaks the wire format itself (``rle_design.policy_socket.serve`` would refuse to send NaN), so
the evaluator's check sees them: every reply is refused (``protocol.non_finite``), no episode
completes, the completion threshold fails and the score is zero.
"""

import glob
import os
import socket

import numpy as np

from rle_design.policy_socket import recv_frame, send_frame


def train(demos_dir: str) -> None:
    actions = [np.load(p)["actions"] for p in sorted(glob.glob(os.path.join(demos_dir, "*.npz")))]
    with open("ckpt.pt", "wb") as f:
        np.save(f, np.concatenate(actions).mean(axis=0).astype(np.float32))


def serve(socket_path: str) -> int:
    with open("ckpt.pt", "rb") as f:
        chunk = np.tile(np.load(f), (8, 1))
    chunk[:, 0] = np.nan
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as sock:
        sock.connect(socket_path)
        n = 0
        while recv_frame(sock)[0]["type"] != "bye":
            send_frame(sock, "actions", {"actions": chunk})
            n += 1
    return n
