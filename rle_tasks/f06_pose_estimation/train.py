"""Train the variant C model from labelled development renders (no meshes, no shape labels).

    nice -n 10 python -m rle_tasks.f06_pose_estimation.train [--steps 1500] [--seed 0] [--out model.pt]

1. Renders public frames (``devserver.labelled_frames``, stick beside the block or raised) and push
   episodes, with their noisy labels (1 mm, 0.01 rad).
2. Estimates the top-face height (most frequent height of red depth points) and takes the
   calibration from the observations; builds the fixed part of ``learned.BevPoseNet``.
3. Pseudo-labels the shapes without shape labels: label-aligned occupancy grids, k-means with three
   clusters, letters from the clusters' symmetries (``solutions.build_templates``).
4. Trains the CNN head on bird's-eye images of the frames' top-face points, augmented by random
   rotations about their centroid (the label rotates with them) and random point dropout
   (occlusion), with an L1 loss on the offset [cm], squared error on (cos, sin) and cross-entropy
   on the shape; one thread or two, seeded.
5. Writes the TorchScript ``model.pt`` (CPU).
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np
import torch
from torch import nn

from .learned import BEV_CELL, BEV_CELLS, BevPoseNet, Head

HERE = Path(__file__).resolve().parent
DEFAULT_OUT = HERE / "solutions" / "reference_c" / "model.pt"
FRAME_SEEDS = range(300, 340)
EPISODE_SEEDS = range(400, 410)
BATCH = 48


def _data(frames_per_seed: int = 30):
    from .devserver import labelled_episode, labelled_frames

    pairs = []
    for s in FRAME_SEEDS:
        pairs += labelled_frames(s, frames_per_seed, raised=s % 4 == 0)
    for s in EPISODE_SEEDS:
        pairs += labelled_episode(s, 60)[::3]
    return pairs


def _top_z(pairs) -> float:
    zs = []
    for obs, _ in pairs[:40]:
        red = (obs["rgb"][..., 0].astype(int) - obs["rgb"][..., 1:].max(-1) > 45) & obs["valid"]
        v, u = np.nonzero(red)
        k, pose, z = obs["K"], obs["T_world_cam"], obs["depth"][v, u]
        cam = np.stack([(u - k[0, 2]) / k[0, 0] * z, (v - k[1, 2]) / k[1, 1] * z, z], 1)
        zs.append((cam @ pose[:3, :3].T + pose[:3, 3])[:, 2])
    hist, edges = np.histogram(np.concatenate(zs), bins=120, range=(0.0, 0.06))
    return float(edges[int(np.argmax(hist))] + 0.00025)


def _tensors(obs):
    rgb = torch.from_numpy(obs["rgb"]).permute(2, 0, 1)[None].float() / 255.0
    depth = torch.from_numpy(obs["depth"].astype(np.float32))[None, None]
    valid = torch.from_numpy(obs["valid"].astype(np.float32))[None, None]
    return rgb, depth, valid


def _pseudo_shapes(points, labels) -> np.ndarray:
    from .solutions.build_templates import _grid, _kmeans, _name

    grids = []
    for p, (x, y, t) in zip(points, labels):
        c, s = math.cos(t), math.sin(t)
        grids.append(_grid((p - (x, y)) @ np.array([[c, -s], [s, c]])))
    grids = np.array(grids)
    lab = _kmeans(grids.reshape(len(grids), -1).astype(float))
    names = {j: _name(grids[lab == j].mean(0) >= 0.5) for j in range(3)}
    if sorted(names.values()) != ["C", "F", "T"]:
        raise RuntimeError(f"shape clusters named {sorted(names.values())}, expected C, F, T")
    ids = {"T": 0, "C": 1, "F": 2}
    return np.array([ids[names[j]] for j in lab])


def _bev_np(p: np.ndarray) -> np.ndarray:
    """``learned.bev`` of ``p`` around its centroid, in numpy (same cells and scaling; tested equal)."""
    cells, cell = BEV_CELLS, BEV_CELL
    idx = np.floor((p - p.mean(0)) / cell).astype(np.int64) + cells // 2
    idx = idx[((idx >= 0) & (idx < cells)).all(1)]
    img = np.zeros(cells * cells, np.float32)
    np.add.at(img, idx[:, 0] * cells + idx[:, 1], 1.0)
    return np.minimum(img / 3.0, 1.0).reshape(1, cells, cells)


def _sample(points, labels, shapes, rng, batch):
    imgs, targets, cls = [], [], []
    for i in rng.integers(0, len(points), batch):
        p, (x, y, t) = points[i], labels[i]
        keep = rng.random(len(p)) > rng.uniform(0.0, 0.3)
        if rng.random() < 0.3:  # a band removed, as a stick would
            n = rng.normal(size=2)
            n /= np.linalg.norm(n)
            d = (p - p.mean(0)) @ n
            keep &= np.abs(d - rng.uniform(-0.04, 0.04)) > rng.uniform(0.005, 0.015)
        p = p[keep] if keep.sum() > 20 else p
        a = rng.uniform(-math.pi, math.pi)
        r = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
        c0 = p.mean(0)
        p = ((p - c0) @ r.T + c0 + rng.normal(0, 0.0005, 2)).astype(np.float32)
        xy = (np.array([x, y]) - c0) @ r.T + c0
        centre = p.astype(np.float64).mean(0)
        imgs.append(_bev_np(p))
        th = t + a
        targets.append([(xy[0] - centre[0]) * 100, (xy[1] - centre[1]) * 100, math.cos(th), math.sin(th)])
        cls.append(shapes[i])
    return torch.from_numpy(np.stack(imgs)), torch.tensor(targets, dtype=torch.float32), torch.tensor(cls)


def train(steps: int, seed: int, out: Path, threads: int = 2, cache: Path | None = None) -> dict:
    torch.manual_seed(seed)
    torch.set_num_threads(threads)
    rng = np.random.default_rng(seed)
    t0 = time.time()
    head = Head()
    if cache is not None and cache.exists():
        z = np.load(cache, allow_pickle=False)
        top_z, k, pose = float(z["top_z"]), torch.from_numpy(z["k"]), torch.from_numpy(z["pose"])
        counts = np.cumsum(z["counts"])[:-1]
        points, labels = np.split(z["points"], counts), list(z["labels"])
        model = BevPoseNet(k, pose, top_z, head)
    else:
        pairs = _data()
        top_z = _top_z(pairs)
        k = torch.from_numpy(pairs[0][0]["K"])
        pose = torch.from_numpy(pairs[0][0]["T_world_cam"])
        model = BevPoseNet(k, pose, top_z, head)
        points, labels = [], []
        with torch.no_grad():
            for obs, lab in pairs:
                p = model.points(*_tensors(obs)).double().numpy()
                if len(p) >= 30:
                    points.append(p)
                    labels.append(lab)
        if cache is not None:
            np.savez(
                cache,
                top_z=top_z,
                k=k.numpy(),
                pose=pose.numpy(),
                points=np.concatenate(points),
                counts=[len(p) for p in points],
                labels=np.array(labels),
            )
    shapes = _pseudo_shapes(points, labels)
    opt = torch.optim.Adam(head.parameters(), lr=2e-3)
    sched = torch.optim.lr_scheduler.CosineAnnealingLR(opt, steps)
    ce = nn.CrossEntropyLoss()
    for step in range(steps):
        img, tgt, cls = _sample(points, labels, shapes, rng, BATCH)
        pred = head(img)
        loss = (pred[:, :2] - tgt[:, :2]).abs().mean() + 4 * ((pred[:, 2:4] - tgt[:, 2:4]) ** 2).mean()
        loss = loss + 0.5 * ce(pred[:, 4:], cls)
        opt.zero_grad()
        loss.backward()
        opt.step()
        sched.step()
        if step % 250 == 0:
            print(f"step {step} loss {loss.item():.4f} ({time.time() - t0:.0f} s)", flush=True)
    head.eval()
    out.parent.mkdir(parents=True, exist_ok=True)
    scripted = torch.jit.script(model)
    torch.jit.save(scripted, str(out))
    loaded = torch.jit.load(str(out))
    probe = loaded(torch.zeros(1, 3, 240, 320), torch.ones(1, 1, 240, 320), torch.ones(1, 1, 240, 320))
    if tuple(probe.shape) != (1, 6):
        raise RuntimeError(f"saved model returns shape {tuple(probe.shape)}, expected (1, 6)")
    n = sum(p.numel() for p in scripted.parameters()) + sum(b.numel() for b in scripted.buffers())
    info = {
        "frames": len(points),
        "top_z": top_z,
        "elements": n,
        "shape_counts": np.bincount(shapes).tolist(),
        "seconds": time.time() - t0,
    }
    print(info)
    return info


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--steps", type=int, default=1500)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT)
    ap.add_argument("--cache", type=Path, default=None, help="npz of the rendered training points (reused)")
    args = ap.parse_args()
    train(args.steps, args.seed, args.out, args.threads, args.cache)


if __name__ == "__main__":
    main()
