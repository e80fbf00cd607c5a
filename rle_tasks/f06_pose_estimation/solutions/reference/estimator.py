"""Classical planar pose estimator (reference of 06-pose-a/b/d): segmentation, plane points, 2-D ICP.

1. Red segmentation of the RGB image (specks of a reddish table removed).
2. Plane points [m] (on a 2 mm grid, thinned to at most 450): with depth, the red pixels lifted to 3-D whose height is within 6 mm of the top
   face (the top face alone); RGB only, the red pixels' rays cut with the top plane and with the table
   plane, rasterised on a 2 mm grid and intersected (a prism's silhouette smeared towards and away
   from the camera; their intersection is the footprint for convex parts).
3. Shape and pose: point-to-point ICP against the three templates in ``templates.npz`` (built
   by ``build_templates.py`` from labelled renders), from eight starting angles per shape on a
   thinned point set; the four best candidates are refined on all points and the smallest symmetric
   chamfer cost picks the shape (RGB only: per shape its best start is refined, and the shape whose
   projected prism best overlaps the red mask, by IoU, wins).
   RGB only: a last ICP against the template of the estimated orientation's bin (the sides' smear
   depends on the view).
4. Tracking: within a trajectory, ICP warm-started from the previous pose; the shape is the running
   vote of the per-frame decisions; a poor fit falls back to the global search.
"""

from pathlib import Path

import numpy as np
from scipy import ndimage
from scipy.spatial import cKDTree

_T = np.load(Path(__file__).with_name("templates.npz"))
TOP_Z = float(_T["top_z"])
GRID = 0.002
MAX_POINTS = 450
N_BINS = 8
_TEMPLATES = {}
_TREES = {}
_state = {}


def _binned(s, theta):
    """Tree of the orientation-binned RGB template of shape ``s`` at ``theta`` (None if not built)."""
    b = int((theta + np.pi) % (2 * np.pi) // (2 * np.pi / N_BINS)) % N_BINS
    key = f"rgb_{s}_b{b}"
    if key not in _TREES:
        _TREES[key] = cKDTree(_T[key]) if key in _T.files else None
    return _TREES[key]


def _templates(mode):
    if mode not in _TEMPLATES:
        pts = [_T[f"{mode}_{s}"] for s in range(3)]
        _TEMPLATES[mode] = pts
        _TREES[mode] = [cKDTree(p) for p in pts]
    return _TEMPLATES[mode], _TREES[mode]


def reset():
    _state.clear()


def _red(rgb):
    """Red pixels, without specks (opening, then components of at least 30 pixels)."""
    c = rgb.astype(np.int16)
    r, g, b = c[..., 0], c[..., 1], c[..., 2]
    mask = ndimage.binary_opening((r > 60) & (r - np.maximum(g, b) > 45))
    labels, n = ndimage.label(mask)
    if n > 1:
        sizes = np.bincount(labels.ravel())
        mask = (sizes >= 30)[labels] & (labels > 0)
    return mask


def _rays(obs, v, u):
    k = obs["K"]
    pose = obs["T_world_cam"]
    d = np.stack([(u - k[0, 2]) / k[0, 0], (v - k[1, 2]) / k[1, 1], np.ones_like(u, dtype=float)], 1)
    return pose[:3, 3], d @ pose[:3, :3].T


def _cut(origin, dirs, z):
    s = (z - origin[2]) / dirs[:, 2]
    return origin[:2] + dirs[:, :2] * s[:, None]


def plane_points(obs, thin=True):
    mask = _red(obs["rgb"])
    v, u = np.nonzero(mask)
    if len(u) < 20:
        return None, None
    if "depth" in obs:
        ok = obs["valid"][v, u]
        v, u = v[ok], u[ok]
        z = obs["depth"][v, u].astype(float)
        origin, dirs = _rays(obs, v.astype(float), u.astype(float))
        pts = origin + dirs * z[:, None]
        pts = pts[np.abs(pts[:, 2] - TOP_Z) < 0.006, :2]
        mode = "depth"
    else:
        origin, dirs = _rays(obs, v.astype(float), u.astype(float))
        hi = np.floor(_cut(origin, dirs, TOP_Z) / GRID).astype(np.int64)
        lo = np.floor(_cut(origin, dirs, 0.0) / GRID).astype(np.int64)
        base = np.minimum(hi.min(0), lo.min(0)) - 2
        size = np.maximum(hi.max(0), lo.max(0)) - base + 3
        if size.max() > 400:
            return None, None
        grids = []
        for cells in (hi, lo):
            g = np.zeros(size, bool)
            g[cells[:, 0] - base[0], cells[:, 1] - base[1]] = True
            grids.append(ndimage.binary_closing(g, iterations=2))
        pts = (np.argwhere(grids[0] & grids[1]) + base + 0.5) * GRID
        mode = "rgb"
    if len(pts) < 20:
        return None, None
    cell = np.unique(np.floor(pts / GRID).astype(np.int64), axis=0)
    if thin:
        cell = cell[:: int(np.ceil(len(cell) / MAX_POINTS))]
    return (cell + 0.5) * GRID, mode


def _rot(t):
    c, s = np.cos(t), np.sin(t)
    return np.array([[c, -s], [s, c]])


def _icp(pts, tree, pose, iters=20, trim=1.0):
    x, y, t = pose
    for _ in range(iters):
        r = _rot(t)
        local = (pts - (x, y)) @ r  # world -> block frame
        dist, idx = tree.query(local)
        keep = dist <= np.quantile(dist, trim) if trim < 1.0 else np.ones(len(dist), bool)
        a, b = pts[keep], tree.data[idx[keep]]
        ca, cb = a.mean(0), b.mean(0)
        h = (b - cb).T @ (a - ca)
        t_new = np.arctan2(h[0, 1] - h[1, 0], h[0, 0] + h[1, 1])
        r = _rot(t_new)
        off = ca - cb @ r.T
        step = abs(t_new - t) + np.hypot(off[0] - x, off[1] - y)
        x, y, t = off[0], off[1], t_new
        if step < 1e-5:
            break
    return np.array([x, y, t])


def _cost(pts, tmpl, tree, obs_tree, pose):
    r = _rot(pose[2])
    d1, _ = tree.query((pts - pose[:2]) @ r)
    world = tmpl @ r.T + pose[:2]
    d2, _ = obs_tree.query(world, distance_upper_bound=0.02)
    d2 = np.minimum(d2, 0.02)
    return float(np.mean(np.minimum(d1, 0.02)) + 0.5 * np.mean(d2))


def _silhouette(obs, tmpl, pose):
    """IoU of the red mask with the projected prism of ``tmpl`` at ``pose`` (RGB shape decision)."""
    r = _rot(pose[2])
    xy = tmpl @ r.T + pose[:2]
    pts = np.concatenate([np.column_stack([xy, np.full(len(xy), z)]) for z in np.linspace(0, TOP_Z, 4)])
    k, cam_pose = obs["K"], obs["T_world_cam"]
    cam = (pts - cam_pose[:3, 3]) @ cam_pose[:3, :3]
    u = np.rint(k[0, 0] * cam[:, 0] / cam[:, 2] + k[0, 2]).astype(int)
    v = np.rint(k[1, 1] * cam[:, 1] / cam[:, 2] + k[1, 2]).astype(int)
    red = _red(obs["rgb"])
    ok = (u >= 0) & (u < red.shape[1]) & (v >= 0) & (v < red.shape[0])
    pred = np.zeros_like(red)
    pred[v[ok], u[ok]] = True
    pred = ndimage.binary_closing(pred, iterations=1)
    union = (pred | red).sum()
    return float((pred & red).sum() / union) if union else 0.0


def _global(pts, mode, obs=None):
    tmpls, trees = _templates(mode)
    coarse = pts[:: int(np.ceil(len(pts) / 150))]
    coarse_tree = cKDTree(coarse)
    c = pts.mean(0)
    cands = []
    for s in range(3):
        for k in range(8):
            pose = _icp(coarse, trees[s], np.array([c[0], c[1], k * np.pi / 4]), iters=10)
            cands.append((_cost(coarse, tmpls[s], trees[s], coarse_tree, pose), s, pose))
    cands.sort(key=lambda e: e[0])
    obs_tree = cKDTree(pts)
    if mode == "rgb" and obs is not None:
        # per shape, its best start refined; the shape whose projected prism matches the mask wins
        best_iou = (-1.0, None, None)
        for s in range(3):
            _, _, pose = next(e for e in cands if e[1] == s)
            pose = _icp(pts, trees[s], pose, iters=40)
            iou = _silhouette(obs, tmpls[s], pose)
            if iou > best_iou[0]:
                best_iou = (iou, s, pose)
        _, s, pose = best_iou
        pose = _icp(pts, trees[s], pose, iters=150)
        return s, pose, _cost(pts, tmpls[s], trees[s], obs_tree, pose)
    best = (np.inf, None, None)
    for _, s, pose in cands[:4]:
        pose = _icp(pts, trees[s], pose, iters=40)
        cost = _cost(pts, tmpls[s], trees[s], obs_tree, pose)
        if cost < best[0]:
            best = (cost, s, pose)
    cost, s, pose = best
    return s, _icp(pts, trees[s], pose, iters=150), cost


def update(obs):
    pts, mode = plane_points(obs)
    if pts is None:
        prev = _state.get("pose")
        if prev is None:
            return (0.0, 0.0, 0.0, 0)
        return (float(prev[0]), float(prev[1]), float(prev[2]), int(_state["shape"]))
    tmpls, trees = _templates(mode)
    prev = _state.get("pose")
    if prev is not None:
        s = _state["shape"]
        pose = _icp(pts, trees[s], prev, iters=60)
        cost = _cost(pts, tmpls[s], trees[s], cKDTree(pts), pose)
        if cost > 2.5 * _state["cost"] + 0.001:
            s_new, pose_g, cost_g = _global(pts, mode, obs)
            if cost_g < cost:
                votes = _state["votes"]
                votes[s_new] += 1
                pose, cost = pose_g, cost_g
                s = int(np.argmax(votes)) if votes[s] < votes[s_new] else s
                if s != s_new:
                    pose = _icp(pts, trees[s], pose, iters=20)
    else:
        s, pose, cost = _global(pts, mode, obs)
        _state["votes"] = np.zeros(3)
        _state["votes"][s] += 1
    if mode == "rgb":
        tree = _binned(s, pose[2])
        if tree is not None:
            pose = _icp(pts, tree, pose, iters=30)
    _state.update(pose=pose, shape=s, cost=cost)
    t = (pose[2] + np.pi) % (2 * np.pi) - np.pi
    return (float(pose[0]), float(pose[1]), float(t), int(s))
