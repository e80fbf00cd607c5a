"""Reference recipe of 05-libero-open: frozen encoder features, spatial-softmax keypoints, a small
action-chunking policy trained by behaviour cloning.

Training (``train``):

* every ``stride``-th frame with views of every demonstration (its ``view_frames``; 1 when the
  dataset has at most 40,000 of them, else 2) goes through the frozen EfficientNet-Lite0 up to its stride-16 stage (the 11 blocks before
  the 192-channel stage): an 8 x 8 x 112 map per view, kept in float16;
* the policy: per view a 1 x 1 convolution to 32 keypoint channels, a spatial softmax giving each
  keypoint's expected (x, y), and the map's average; both views, the 8-D state and a one-hot of the
  instruction (the instructions seen in training) feed a 2 x 512 MLP that predicts the next
  ``CHUNK`` actions (L1 loss, as in action chunking with transformers);
* augmentation: the maps are shifted by up to one cell (replicate padding), which is a 16-pixel
  image shift; AdamW, batch 256, seeded; it stops at ``MAX_STEPS`` or when ``TIME_BUDGET_S`` of
  wall time have passed since ``train`` started, well inside the 1,800 s.

Serving (``serve``): the same encoder on both views, the chunk's first ``EXECUTE`` actions with the
gripper snapped to -1 / +1.
"""

import glob
import json
import os
import time

import numpy as np
import torch
from torch import nn
from torch.nn import functional as F

from rle_design.encoders import load_encoder, preprocess
from rle_design.policy_socket import serve as _serve

SEED = 0
CHUNK = 8
EXECUTE = 4
KEYPOINTS = 32
BLOCKS = 11
"""Encoder blocks run: through the 112-channel stage (stride 16: 8 x 8 at 128 px)."""
MAX_STEPS = 20_000
TIME_BUDGET_S = 1400.0
BATCH = 256
MAX_FRAMES_STRIDE_1 = 40_000


def _threads() -> None:
    torch.set_num_threads(max(1, min(8, os.cpu_count() or 1)))


def encode(net, images: np.ndarray) -> torch.Tensor:
    """uint8 (N, 128, 128, 3) -> float16 (N, 112, 8, 8) mid-level maps of the frozen encoder."""
    out = []
    with torch.no_grad():
        for s in range(0, len(images), 64):
            x = preprocess(images[s : s + 64])
            x = F.relu6(net._bn0(net._conv_stem(x)))
            for b in net._blocks[:BLOCKS]:
                x = b(x)
            out.append(x.half())
    return torch.cat(out)


class Policy(nn.Module):
    def __init__(self, channels: int, n_instructions: int, state_dim: int = 8, action_dim: int = 7):
        super().__init__()
        self.key = nn.ModuleList([nn.Conv2d(channels, KEYPOINTS, 1) for _ in range(2)])
        width = 2 * (2 * KEYPOINTS + channels) + state_dim + n_instructions
        self.mlp = nn.Sequential(
            nn.Linear(width, 512),
            nn.ReLU(),
            nn.Linear(512, 512),
            nn.ReLU(),
            nn.Linear(512, CHUNK * action_dim),
        )
        self.action_dim = action_dim

    def forward(self, maps: list[torch.Tensor], state: torch.Tensor, task: torch.Tensor) -> torch.Tensor:
        parts = []
        for conv, m in zip(self.key, maps):
            m = m.float()
            logits = conv(m).flatten(2)  # (B, K, H*W)
            h, w = m.shape[-2:]
            ys, xs = torch.meshgrid(torch.linspace(-1, 1, h), torch.linspace(-1, 1, w), indexing="ij")
            p = logits.softmax(-1)
            parts += [p @ xs.reshape(-1), p @ ys.reshape(-1), m.mean((2, 3))]
        x = torch.cat([*parts, state, task], 1)
        return self.mlp(x).view(-1, CHUNK, self.action_dim)


def _shift(maps: torch.Tensor, gen: torch.Generator) -> torch.Tensor:
    """Shift each map by -1, 0 or +1 cells in x and y (replicate padding)."""
    b = maps.shape[0]
    padded = F.pad(maps.float(), (1, 1, 1, 1), mode="replicate")
    dx = torch.randint(0, 3, (b,), generator=gen)
    dy = torch.randint(0, 3, (b,), generator=gen)
    h, w = maps.shape[-2:]
    rows = (torch.arange(h)[None, :] + dy[:, None])[:, None, :, None].expand(b, maps.shape[1], h, w + 2)
    out = torch.gather(padded, 2, rows)
    cols = (torch.arange(w)[None, :] + dx[:, None])[:, None, None, :].expand(b, maps.shape[1], h, w)
    return torch.gather(out, 3, cols)


def _view_frames(ep) -> np.ndarray:
    """Frames with views that an action follows (every frame when the dataset has no list)."""
    n = len(ep["actions"])
    frames = ep["view_frames"] if "view_frames" in ep.files else np.arange(n + 1)
    return frames[frames < n]


def train(demos_dir: str) -> None:
    start = time.monotonic()
    torch.manual_seed(SEED)
    _threads()
    files = sorted(glob.glob(os.path.join(demos_dir, "*.npz")))
    framed = [_view_frames(np.load(f)) for f in files]
    stride = 1 if sum(len(v) for v in framed) <= MAX_FRAMES_STRIDE_1 else 2
    net = load_encoder()
    views = ([], [])
    states, targets, langs = [], [], []
    for f, frames in zip(files, framed):
        ep = np.load(f)
        a = ep["actions"].astype(np.float32)
        rows = np.arange(0, len(frames), stride)  # rows of the views; frames[rows] act on
        t = frames[rows]
        for k, name in enumerate(("agentview", "wrist")):
            views[k].append(encode(net, ep[name][rows]))
        states.append(ep["state"][t].astype(np.float32))
        pad = np.concatenate([a, np.repeat(a[-1:], CHUNK, 0)])
        targets.append(np.stack([pad[i : i + CHUNK] for i in t]))
        langs += [str(ep["language"])] * len(t)
    instructions = sorted(set(langs))
    index = {s: i for i, s in enumerate(instructions)}
    maps = [torch.cat(v) for v in views]
    state = torch.as_tensor(np.concatenate(states))
    mu, sd = state.mean(0), state.std(0) + 1e-3
    task = F.one_hot(torch.tensor([index[s] for s in langs]), len(instructions)).float()
    y = torch.as_tensor(np.concatenate(targets))
    policy = Policy(maps[0].shape[1], len(instructions))
    opt = torch.optim.AdamW(policy.parameters(), lr=3e-4, weight_decay=1e-4)
    gen = torch.Generator().manual_seed(SEED)
    n = len(y)
    steps = 0
    while steps < MAX_STEPS:
        steps += 1
        idx = torch.randint(0, n, (BATCH,), generator=gen)
        pred = policy([_shift(m[idx], gen) for m in maps], (state[idx] - mu) / sd, task[idx])
        loss = F.l1_loss(pred, y[idx])
        opt.zero_grad()
        loss.backward()
        opt.step()
        if time.monotonic() - start > TIME_BUDGET_S:
            break
    torch.save(
        {
            "policy": policy.state_dict(),
            "mu": mu,
            "sd": sd,
            "instructions": instructions,
            "channels": maps[0].shape[1],
        },
        "ckpt.pt",
    )
    with open("meta.json", "w") as f:
        json.dump(
            {
                "frames": n,
                "stride": stride,
                "steps": steps,
                "loss": float(loss),
                "train_s": time.monotonic() - start,
            },
            f,
        )


def serve(socket_path: str) -> int:
    _threads()
    ckpt = torch.load("ckpt.pt", map_location="cpu", weights_only=True)
    instructions = list(ckpt["instructions"])
    policy = Policy(int(ckpt["channels"]), len(instructions))
    policy.load_state_dict(ckpt["policy"])
    policy.eval()
    net = load_encoder()

    def act(request):
        maps = [encode(net, request.views[k : k + 1]) for k in range(2)]
        state = (torch.as_tensor(request.state[None]) - ckpt["mu"]) / ckpt["sd"]
        task = torch.zeros(1, len(instructions))
        if request.instruction in instructions:
            task[0, instructions.index(request.instruction)] = 1.0
        with torch.no_grad():
            chunk = policy(maps, state, task)[0, :EXECUTE].numpy().astype(np.float32)
        chunk[:, 6] = np.where(chunk[:, 6] >= 0.0, 1.0, -1.0)
        return np.clip(chunk, -1.0, 1.0)

    return _serve(socket_path, act)
