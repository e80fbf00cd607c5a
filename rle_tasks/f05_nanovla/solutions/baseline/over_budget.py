"""Baseline recipe that must fail: its training never ends (an epoch loop without a stopping rule).

The replay stops it at the card's 1,800 s plus 120 s (``sandbox.timeout``): no checkpoint, score zero.
"""

import time

from rle_design.policy_socket import serve as _serve


def train(demos_dir: str) -> None:
    epoch = 0
    while True:  # "until the loss converges", which it never reports
        time.sleep(1.0)
        epoch += 1


def serve(socket_path: str) -> int:
    return _serve(socket_path, lambda request: None)
