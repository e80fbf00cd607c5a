"""Build the reference estimator's ``templates.npz`` from labelled development renders only.

Renders public frames (``N_SEEDS`` seeds from ``SEED``, 90 frames each) with the stick raised, as the development server does,
with its label noise (1 mm, 0.01 rad) and without shape labels. Per frame, the estimator's own plane
points are moved into the labelled block frame and rasterised on a 2 mm grid; the frames are
clustered into three shapes (k-means on the occupancy grids) and each cluster's template is the set
of cells occupied in at least half of its frames. Clusters are named by the letters' symmetries:
F has no mirror axis; of the two with one, T leaves two large empty regions in its bounding
box, C one.
For the RGB plane points, whose side smear depends on the view, templates are also kept per
orientation bin (eight bins of the labelled theta). The top-face height is the most frequent height of the red depth points (renders of the RGB-D variants).

    python -m rle_tasks.f06_pose_estimation.solutions.build_templates
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
from scipy import ndimage

from rle_tasks.f06_pose_estimation.devserver import LABEL_NOISE, labelled_frames

HERE = Path(__file__).resolve().parent
OUT = HERE / "reference" / "templates.npz"
SEED = 7
N_FRAMES = 90
N_SEEDS = 4
N_BINS = 8
GRID = 0.002
HALF = 0.1


def _estimator():
    spec = importlib.util.spec_from_file_location("ref_estimator", HERE / "reference" / "estimator.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _grid(points: np.ndarray) -> np.ndarray:
    n = int(round(2 * HALF / GRID))
    idx = np.floor((points + HALF) / GRID).astype(int)
    idx = idx[((idx >= 0) & (idx < n)).all(1)]
    g = np.zeros((n, n), bool)
    g[idx[:, 0], idx[:, 1]] = True
    return ndimage.binary_closing(g, iterations=1)


def _kmeans(x: np.ndarray, k: int = 3, iters: int = 50) -> np.ndarray:
    centres = [x[0]]
    for _ in range(k - 1):
        d = np.min([((x - c) ** 2).sum(1) for c in centres], 0)
        centres.append(x[int(np.argmax(d))])
    c = np.array(centres)
    for _ in range(iters):
        lab = np.argmin(((x[:, None] - c[None]) ** 2).sum(-1), 1)
        c = np.array([x[lab == j].mean(0) for j in range(k)])
    return lab


def _name(template: np.ndarray) -> str:
    sym = max((template == template[::-1]).mean(), (template == template[:, ::-1]).mean())
    if sym < 0.97:
        return "F"
    rows, cols = np.nonzero(template.any(1))[0], np.nonzero(template.any(0))[0]
    box = ~template[rows.min() : rows.max() + 1, cols.min() : cols.max() + 1]
    regions, n = ndimage.label(box)
    big = sum(int((regions == i).sum()) >= 0.05 * box.size for i in range(1, n + 1))
    return "T" if big >= 2 else "C"


def _templates(frames, est, depth: bool) -> tuple[dict[str, np.ndarray], np.ndarray, list[str]]:
    """Templates by letter, the frames' label-aligned grids and each frame's letter."""
    grids = []
    for obs, label in frames:
        if not depth:
            obs = {k: v for k, v in obs.items() if k not in ("depth", "valid")}
        pts, _ = est.plane_points(obs, thin=False)
        x, y, t = label
        c, s = np.cos(t), np.sin(t)
        local = (pts - (x, y)) @ np.array([[c, -s], [s, c]])
        grids.append(_grid(local))
    grids = np.array(grids)
    lab = _kmeans(grids.reshape(len(grids), -1).astype(float))
    out, names = {}, {}
    for j in range(3):
        occ = grids[lab == j].mean(0) >= 0.5
        names[j] = _name(occ)
        out[names[j]] = (np.argwhere(occ) + 0.5) * GRID - HALF
    if sorted(out) != ["C", "F", "T"]:
        raise RuntimeError(f"clusters named {sorted(out)}, expected C, F, T")
    return out, grids, [names[j] for j in lab]


def _binned(frames, grids: np.ndarray, letters: list[str]) -> dict[str, np.ndarray]:
    """RGB templates per letter and orientation bin (the smear of the sides depends on the view)."""
    bins = np.array([int((lab[2] + np.pi) // (2 * np.pi / N_BINS)) % N_BINS for _, lab in frames])
    out = {}
    for i, name in enumerate(("T", "C", "F")):
        for b in range(N_BINS):
            sel = (np.array(letters) == name) & (bins == b)
            if sel.sum() >= 3:
                occ = grids[sel].mean(0) >= 0.5
                out[f"rgb_{i}_b{b}"] = (np.argwhere(occ) + 0.5) * GRID - HALF
    return out


def build() -> dict[str, np.ndarray]:
    frames = [f for k in range(N_SEEDS) for f in labelled_frames(SEED + k, N_FRAMES, raised=True)]
    zs = []
    for obs, _ in frames[:20]:
        red = (obs["rgb"][..., 0].astype(int) - obs["rgb"][..., 1:].max(-1) > 45) & obs["valid"]
        v, u = np.nonzero(red)
        k, pose = obs["K"], obs["T_world_cam"]
        z = obs["depth"][v, u]
        cam = np.stack([(u - k[0, 2]) / k[0, 0] * z, (v - k[1, 2]) / k[1, 1] * z, z], 1)
        zs.append((cam @ pose[:3, :3].T + pose[:3, 3])[:, 2])
    heights = np.concatenate(zs)
    hist, edges = np.histogram(heights, bins=120, range=(0.0, 0.06))
    top_z = float(edges[int(np.argmax(hist))] + 0.00025)
    np.savez(OUT, top_z=top_z, **{f"depth_{i}": np.zeros((1, 2)) for i in range(3)})
    est = _estimator()
    arrays: dict[str, np.ndarray] = {"top_z": np.array(top_z), "label_noise": np.array(LABEL_NOISE)}
    for mode, depth in (("depth", True), ("rgb", False)):
        t, grids, letters = _templates(frames, est, depth)
        for i, name in enumerate(("T", "C", "F")):
            arrays[f"{mode}_{i}"] = t[name]
        if not depth:
            arrays.update(_binned(frames, grids, letters))
    np.savez(OUT, **arrays)
    return arrays


if __name__ == "__main__":
    arrays = build()
    print(
        f"top_z {float(arrays['top_z']):.4f} m; template cells:",
        {k: len(v) for k, v in arrays.items() if v.ndim == 2},
    )
