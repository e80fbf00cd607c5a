"""Reference recipe of family 05 (LIBERO and the RoboTwin stand-in): frozen encoder maps,
spatial-softmax keypoints, a small action-chunking policy trained by behaviour cloning.

The environment is told by the demonstrations' view names (``ENVS``: ``agentview`` and ``wrist`` on
LIBERO, ``head`` and ``front`` on the stand-in) and kept in the checkpoint for serving.

Training (``train``):

* every frame with views of every demonstration (all of the stand-in's; LIBERO's dataset has the
  views of every 4th frame, ``view_frames``) goes through the frozen EfficientNet-Lite0 up to its
  stride-8 stage (the first ``BLOCKS`` blocks): a 16 x 16 x 40 map per view, kept in float16;
* the policy: per view a 1 x 1 convolution to ``KEYPOINTS`` keypoint channels, a spatial softmax
  giving each keypoint's expected (x, y); both views' keypoints, the state entries the environment
  lets the policy see (``state``), a one-hot of the instruction and the episode time (the request's
  ``step``) feed a 2 x 512 MLP that predicts the next ``chunk`` actions, standardised per dimension
  (L1 loss, as in action chunking with transformers);
* on the open track no augmentation: the cameras do not move there, and a shifted map with an
  unchanged label teaches the policy to ignore where the objects are (it halved the grasp precision
  in development); ``AUGMENT`` > 0 (the robust track's reference) adds that many perturbed copies of
  every frame (``augment``: table colour, light, colour cast, distractor boxes, a shift of a few
  pixels for a moved camera), encoded beside the original with the same labels;
* AdamW, batch 256, seeded; it stops at ``MAX_STEPS`` or when ``TIME_BUDGET_S`` of wall time have
  passed since ``train`` started, well inside the 1,800 s.

Serving (``serve``): the same encoder on both views, the chunk's first ``execute`` actions with the
grippers snapped to their two commands. An instruction not seen in training (a paraphrase on the
robust tracks) takes the one-hot of the trained instruction nearest to it by the bundle's text features
(``rle_design.encoders.text_features``, cosine).
"""

import glob
import json
import os
import time

import numpy as np
import torch
from torch import nn
from torch.nn import functional as F

from rle_design.encoders import load_encoder, preprocess, text_features
from rle_design.policy_socket import serve as _serve

SEED = 0
ENVS = {
    "standin": {
        "views": ("head", "front"),
        "action_dim": 14,
        "chunk": 10,
        "execute": 5,
        "horizon": 300.0,
        "grippers": (6, 13),
        "grip": (0.0, 1.0),
        "state": [6, 7, 14, 15],
    },
    "libero": {
        "views": ("agentview", "wrist"),
        "action_dim": 7,
        "chunk": 8,
        "execute": 4,
        "horizon": 520.0,
        "grippers": (6,),
        "grip": (-1.0, 1.0),
        "state": list(range(8)),
    },
}
"""Per environment: view names, action size, the predicted ``chunk`` and the ``execute``-d part of
it (LIBERO: 4, the dataset's view stride, so a request falls where training frames do), the time
scale ``horizon`` [control steps], the gripper entries of an action and their two commands, and the
state entries the policy sees. The stand-in's are its four finger positions: its joint angles are
left out, because its actions are joint targets, nearly the current angle plus a small step, so a
policy that sees them learns to copy them and drifts in closed loop. LIBERO's actions are end-effector
deltas, which no state entry gives away: the policy sees all 8 (end-effector pose and fingers)."""
KEYPOINTS = 32
BLOCKS = 5
"""Encoder blocks run: through the 40-channel stage (stride 8: 16 x 16 at 128 px)."""
MAX_STEPS = 8_000
TIME_BUDGET_S = 1700.0
"""Wall-time guard [s] from the start of ``train``: the sandbox allows 1,920 s (1,800 plus the 120 s
allowance); 220 s are left for the imports before ``train`` and for saving. Unloaded, training ends at
``MAX_STEPS`` first (417 s open, 1,056 s with two augmented copies), so the guard changes nothing there; on
a machine up to 1.6 times slower it still does (at 1,300 s it cut the augmented training of a fresh
``make demo`` on this shared machine, and that run scored 4 of 12 instead of 5)."""
LR = 3e-3
"""Peak learning rate (cosine decay to 0 over ``MAX_STEPS``): on five held-out demonstrations per
task the chunk's L1 error after 3,000 steps was 0.082 at 3e-4, 0.039 at 1e-3 and 0.024 at 3e-3."""
BATCH = 256

AUGMENT = 0
"""Perturbed copies of every frame (0: none)."""
SHIFT_PX = 3
"""Largest image shift of an augmented copy [px] (a 3 cm camera move at about 1 m is up to 4.6 px)."""
TABLE_TOLERANCE = 40
"""A pixel is taken for the table when every channel is within this of the view's commonest colour
(0-255)."""

THREADS = 2
"""torch threads, fixed so that the trained weights do not depend on the machine's core count."""


def _threads() -> None:
    torch.set_num_threads(THREADS)


def encode(net, images: np.ndarray) -> torch.Tensor:
    """uint8 (N, 128, 128, 3) -> float16 (N, 40, 16, 16) maps of the frozen encoder."""
    out = []
    with torch.no_grad():
        for s in range(0, len(images), 128):
            x = preprocess(images[s : s + 128])
            x = F.relu6(net._bn0(net._conv_stem(x)))
            for b in net._blocks[:BLOCKS]:
                x = b(x)
            out.append(x.half())
    return torch.cat(out)


def table_colour(images: np.ndarray) -> np.ndarray:
    """The commonest colour of a view (its table), from frames (N, H, W, 3), in steps of 8."""
    q = images[:: max(1, len(images) // 8)].reshape(-1, 3) // 8
    keys, counts = np.unique(q, axis=0, return_counts=True)
    return keys[counts.argmax()].astype(np.float32) * 8 + 4


def augment(images: np.ndarray, table: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """One perturbed copy of uint8 frames (N, H, W, 3), a fresh look per frame: the table's pixels
    recoloured (shading kept), the light's intensity and colour cast changed, two to four small boxes
    of random colour pasted, the image shifted by up to ``SHIFT_PX``."""
    n, h, w, _ = images.shape
    x = images.astype(np.float32)
    mask = (np.abs(x - table).max(-1, keepdims=True) < TABLE_TOLERANCE).astype(np.float32)
    recolour = rng.uniform(0.15, 0.9, (n, 1, 1, 3)).astype(np.float32) * 255 / np.maximum(table, 1)
    x = x * (1 + mask * (recolour - 1))
    x = x * rng.uniform(0.45, 1.15, (n, 1, 1, 1)) * rng.uniform(0.85, 1.15, (n, 1, 1, 3))
    for i in range(n):
        for _ in range(int(rng.integers(2, 5))):
            bh, bw = rng.integers(3, 9, 2)
            r, c = rng.integers(0, h - bh), rng.integers(0, w - bw)
            x[i, r : r + bh, c : c + bw] = rng.uniform(10, 245, 3)
        dy, dx = rng.integers(-SHIFT_PX, SHIFT_PX + 1, 2)
        x[i] = np.roll(x[i], (int(dy), int(dx)), axis=(0, 1))
    return np.clip(x, 0, 255).astype(np.uint8)


class Policy(nn.Module):
    def __init__(self, channels: int, n_instructions: int, state_dim: int, action_dim: int, chunk: int):
        super().__init__()
        self.key = nn.ModuleList([nn.Conv2d(channels, KEYPOINTS, 1) for _ in range(2)])
        width = 2 * 2 * KEYPOINTS + state_dim + n_instructions + 1
        self.mlp = nn.Sequential(
            nn.Linear(width, 512),
            nn.ReLU(),
            nn.Linear(512, 512),
            nn.ReLU(),
            nn.Linear(512, chunk * action_dim),
        )
        self.action_dim, self.chunk = action_dim, chunk

    def forward(self, maps, state, task, time_in):
        parts = []
        for conv, m in zip(self.key, maps):
            m = m.float()
            logits = conv(m).flatten(2)  # (B, K, H*W)
            h, w = m.shape[-2:]
            ys, xs = torch.meshgrid(torch.linspace(-1, 1, h), torch.linspace(-1, 1, w), indexing="ij")
            p = logits.softmax(-1)
            parts += [p @ xs.reshape(-1), p @ ys.reshape(-1)]
        x = torch.cat([*parts, state, task, time_in], 1)
        return self.mlp(x).view(-1, self.chunk, self.action_dim)


def environment(files: list[str]) -> str:
    """The environment of a dataset, told by its first demonstration's view names."""
    keys = set(np.load(files[0]).files)
    for name, env in ENVS.items():
        if set(env["views"]) <= keys:
            return name
    raise ValueError(f"no views of a known environment in {files[0]}: {sorted(keys)}")


def train(demos_dir: str) -> None:
    start = time.monotonic()
    torch.manual_seed(SEED)
    _threads()
    files = sorted(glob.glob(os.path.join(demos_dir, "*.npz")))
    name = environment(files)
    env = ENVS[name]
    chunk, horizon, seen = env["chunk"], env["horizon"], env["state"]
    net = load_encoder()
    rng = np.random.default_rng(SEED)
    tables = None
    views = ([], [])
    states, targets, langs, times = [], [], [], []
    for f in files:
        ep = np.load(f)
        a = ep["actions"].astype(np.float32)
        n = len(a)
        framed = ep["view_frames"] if "view_frames" in ep.files else np.arange(n + 1)
        rows = np.nonzero(framed < n)[0]  # images of the frames an action follows
        t = framed[rows]
        if AUGMENT and tables is None:
            tables = [table_colour(ep[v]) for v in env["views"]]
        for k, v in enumerate(env["views"]):
            frames = ep[v][rows]
            views[k].append(encode(net, frames))
            for _ in range(AUGMENT):
                views[k].append(encode(net, augment(frames, tables[k], rng)))
        pad = np.concatenate([a, np.repeat(a[-1:], chunk, 0)])
        for _ in range(1 + AUGMENT):
            states.append(ep["state"][t][:, seen].astype(np.float32))
            targets.append(np.stack([pad[i : i + chunk] for i in t]))
            langs += [str(ep["language"])] * len(t)
            times.append(t.astype(np.float32) / horizon)
    instructions = sorted(set(langs))
    index = {s: i for i, s in enumerate(instructions)}
    maps = [torch.cat(v) for v in views]
    state = torch.as_tensor(np.concatenate(states))
    mu, sd = state.mean(0), state.std(0) + 1e-3
    task = F.one_hot(torch.tensor([index[s] for s in langs]), len(instructions)).float()
    t_in = torch.as_tensor(np.concatenate(times))[:, None]
    y = torch.as_tensor(np.concatenate(targets))
    dim = env["action_dim"]
    a_mu, a_sd = y.reshape(-1, dim).mean(0), y.reshape(-1, dim).std(0) + 1e-3
    y = (y - a_mu) / a_sd
    policy = Policy(maps[0].shape[1], len(instructions), len(seen), dim, chunk)
    opt = torch.optim.AdamW(policy.parameters(), lr=LR, weight_decay=1e-4)
    sched = torch.optim.lr_scheduler.CosineAnnealingLR(opt, MAX_STEPS)
    gen = torch.Generator().manual_seed(SEED)
    n = len(y)
    steps = 0
    while steps < MAX_STEPS:
        steps += 1
        idx = torch.randint(0, n, (BATCH,), generator=gen)
        pred = policy([m[idx] for m in maps], (state[idx] - mu) / sd, task[idx], t_in[idx])
        loss = F.l1_loss(pred, y[idx])
        opt.zero_grad()
        loss.backward()
        opt.step()
        sched.step()
        if time.monotonic() - start > TIME_BUDGET_S:
            break
    torch.save(
        {
            "policy": policy.state_dict(),
            "mu": mu,
            "sd": sd,
            "a_mu": a_mu,
            "a_sd": a_sd,
            "instructions": instructions,
            "channels": maps[0].shape[1],
            "env": name,
        },
        "ckpt.pt",
    )
    with open("meta.json", "w") as f:
        json.dump(
            {
                "env": name,
                "frames": n,
                "steps": steps,
                "loss": loss.item(),
                "train_s": time.monotonic() - start,
            },
            f,
        )


def nearest_instruction(text: str, instructions: list[str], known: np.ndarray | None = None) -> int:
    """Index of the trained instruction a request's ``text`` stands for: the text itself, else the
    nearest by the bundle's text features (cosine; ``known``: the instructions' features)."""
    if text in instructions:
        return instructions.index(text)
    if known is None:
        known = text_features(instructions)
    return int(np.argmax(known @ text_features([text])[0]))


def load_policy(path: str = "ckpt.pt"):
    """The serving function ``request -> (execute, action_dim) actions`` of a checkpoint, and the
    name of its environment."""
    _threads()
    ckpt = torch.load(path, map_location="cpu", weights_only=True)
    env = ENVS[ckpt["env"]]
    instructions = list(ckpt["instructions"])
    seen, grippers = env["state"], list(env["grippers"])
    low, high = env["grip"]
    policy = Policy(int(ckpt["channels"]), len(instructions), len(seen), env["action_dim"], env["chunk"])
    policy.load_state_dict(ckpt["policy"])
    policy.eval()
    net = load_encoder()
    known = text_features(instructions)

    def act(request):
        maps = [encode(net, request.views[k : k + 1]) for k in range(2)]
        state = (torch.as_tensor(request.state[None, seen]) - ckpt["mu"]) / ckpt["sd"]
        task = torch.zeros(1, len(instructions))
        task[0, nearest_instruction(request.instruction, instructions, known)] = 1.0
        t_in = torch.tensor([[request.step / env["horizon"]]], dtype=torch.float32)
        with torch.no_grad():
            chunk = policy(maps, state, task, t_in)[0, : env["execute"]] * ckpt["a_sd"] + ckpt["a_mu"]
        chunk = chunk.numpy().astype(np.float32)
        chunk[:, grippers] = np.where(chunk[:, grippers] >= (low + high) / 2, high, low)
        return chunk

    return act, ckpt["env"]


def serve(socket_path: str) -> int:
    act, env = load_policy()
    return _serve(socket_path, act, env=env)
