"""Family 05 serving: latency of one policy request over the socket protocol, and the projected wall
time of a full evaluation set on N workers.

A served ``solution.py`` runs in the project sandbox and answers each ``act`` request (two 128 x 128
views, the 8-D state) with a chunk; the latency is the evaluator's round trip (encode, send, the
policy's work, receive, check). Two policies: ``constant`` (the protocol's own cost) and ``encoder``
(EfficientNet-Lite0 features of both views on CPU, one thread, then a linear head: what a frozen-
encoder recipe pays per request). The projection combines the measured step rates and the latency:
only the observation at each request is rendered, so an episode of H steps with chunks of k actions
costs H / rate_without_views + (H / k) x (view cost + latency), the view cost being
1 / rate_rendered - 1 / rate_without_views; 500 episodes over N workers take ceil(500 / N) episodes
each.

    .venv/bin/python -m benchmarks libero_serving [--requests 200] [--chunk 8] [--horizon 520]
"""

from __future__ import annotations

import argparse
import json
import math
import tempfile
import time
from pathlib import Path

import numpy as np

from benchmarks.libero_step import _rate
from rle_design.policy_socket import VIEW_SHAPE, Request
from rle_tasks.envs.libero.client import serving

POLICIES = {
    "constant": """
import numpy as np
from rle_design.policy_socket import serve as _serve

def serve(socket_path):
    chunk = np.zeros(({k}, 7), np.float32)
    return _serve(socket_path, lambda req: chunk)
""",
    "encoder": """
import numpy as np
import torch
from rle_design.encoders import features, load_encoder
from rle_design.policy_socket import serve as _serve

def serve(socket_path):
    torch.set_num_threads(1)
    net = load_encoder()
    head = np.random.default_rng(0).normal(0, 1e-3, (2 * 1280 + 8, 7 * {k})).astype(np.float32)

    def act(req):
        f = features(net, req.views).reshape(-1)
        return np.tanh(np.concatenate([f, req.state]) @ head).reshape({k}, 7)

    return _serve(socket_path, act)
""",
}


def _latency(source: str, requests: int) -> dict:
    rng = np.random.default_rng(0)
    req = Request(
        "put the bowl on the plate", rng.integers(0, 256, VIEW_SHAPE, dtype=np.uint8), np.zeros(8, np.float32)
    )
    with tempfile.TemporaryDirectory() as tmp:
        (Path(tmp) / "solution.py").write_text(source)
        with serving(Path(tmp), request_timeout_s=60.0) as policy:
            for _ in range(5):  # warm-up
                policy.act(req)
            times = []
            for _ in range(requests):
                t0 = time.perf_counter()
                policy.act(req)
                times.append(time.perf_counter() - t0)
    t = np.array(times) * 1e3
    return {"median_ms": round(float(np.median(t)), 2), "p95_ms": round(float(np.percentile(t, 95)), 2)}


def main() -> int:
    p = argparse.ArgumentParser()
    p.add_argument("--requests", type=int, default=200)
    p.add_argument("--chunk", type=int, default=8)
    p.add_argument("--horizon", type=int, default=520, help="steps per episode (LIBERO-10's horizon)")
    p.add_argument("--episodes", type=int, default=500)
    p.add_argument("--out", default="out/bench/libero_serving.json")
    a = p.parse_args()
    res: dict = {"latency": {}, "chunk": a.chunk}
    for name, src in POLICIES.items():
        res["latency"][name] = _latency(src.format(k=a.chunk), a.requests)
        print(name, json.dumps(res["latency"][name]), flush=True)
    rate = _rate(True, 60)  # rendered steps per second, as benchmarks.libero_step measures them
    bare = _rate(True, 60, views=False)  # the steps between requests
    res["rendered_steps_per_s"] = round(rate, 1)
    res["steps_without_views_per_s"] = round(bare, 1)
    view_s = max(0.0, 1.0 / rate - 1.0 / bare)
    per_episode = {
        name: a.horizon / bare + math.ceil(a.horizon / a.chunk) * (view_s + lat["median_ms"] / 1e3)
        for name, lat in res["latency"].items()
    }
    res["episode_s_at_horizon"] = {k: round(v, 1) for k, v in per_episode.items()}
    res["projected_h"] = {
        f"{n}_workers": {k: round(math.ceil(a.episodes / n) * v / 3600, 2) for k, v in per_episode.items()}
        for n in (1, 8, 32, 100)
    }
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out).write_text(json.dumps(res, indent=2))
    print(json.dumps(res, indent=2))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
