"""The learned estimator of 06-pose-c: in-graph top-face points, a bird's-eye occupancy image, a small CNN.

``BevPoseNet`` is a TorchScript-able module with the variant C signature
``forward(rgb (1,3,H,W) in [0,1], depth (1,1,H,W) [m], valid (1,1,H,W)) -> (1, 6)``:

1. red pixels (fixed thresholds) with valid depth are lifted to world points with the published
   calibration (buffers), and those within 6 mm of the top-face height are kept;
2. their xy centroid ``c`` anchors a ``BEV_CELLS`` x ``BEV_CELLS`` occupancy image of ``BEV_CELL`` m
   cells (``bev``; the same function builds the training images);
3. the CNN maps the image to (dx, dy) [cm], (cos theta, sin theta) and three shape logits; the
   output is ``(c + dx, atan2(sin, cos), logits)``.

Only the CNN is trained (``train.py``); the rest is fixed geometry from the calibration.
"""

from __future__ import annotations

import torch
from torch import nn

BEV_CELLS = 72
BEV_CELL = 0.003
"""Bird's-eye image size [cells] and cell size [m] (a 21.6 cm window)."""
BAND = 0.006
"""Half width of the kept height band around the top face [m]."""


def bev(points: torch.Tensor, centre: torch.Tensor, cells: int = 72, cell: float = 0.003) -> torch.Tensor:
    """``(1, 1, cells, cells)`` occupancy of world xy ``points`` ``(N, 2)`` around ``centre`` ``(2,)``."""
    idx = torch.floor((points - centre) / cell).long() + cells // 2
    inside = (idx[:, 0] >= 0) & (idx[:, 0] < cells) & (idx[:, 1] >= 0) & (idx[:, 1] < cells)
    idx = idx[inside]
    flat = idx[:, 0] * cells + idx[:, 1]
    img = torch.zeros(cells * cells)
    img.index_put_((flat,), torch.ones(flat.shape[0]), accumulate=True)
    return torch.clamp(img / 3.0, max=1.0).reshape(1, 1, cells, cells)


class Head(nn.Module):
    """The trained part: BEV image -> (dx, dy [cm], cos, sin, 3 logits)."""

    def __init__(self) -> None:
        super().__init__()
        self.features = nn.Sequential(
            nn.Conv2d(1, 16, 3, stride=2, padding=1),
            nn.ReLU(),
            nn.Conv2d(16, 32, 3, stride=2, padding=1),
            nn.ReLU(),
            nn.Conv2d(32, 64, 3, stride=2, padding=1),
            nn.ReLU(),
            nn.Conv2d(64, 64, 3, padding=1),
            nn.ReLU(),
        )
        self.fc = nn.Sequential(nn.Flatten(), nn.Linear(64 * 9 * 9, 128), nn.ReLU(), nn.Linear(128, 7))

    def forward(self, img: torch.Tensor) -> torch.Tensor:
        return self.fc(self.features(img))


class BevPoseNet(nn.Module):
    """Full model: fixed geometry + ``Head``.

    Args:
        k: ``(3, 3)`` intrinsics [px].
        world_from_camera: ``(4, 4)`` OpenCV camera to world [m].
        top_z: Top-face height [m].
        head: The trained head.
    """

    def __init__(self, k: torch.Tensor, world_from_camera: torch.Tensor, top_z: float, head: Head) -> None:
        super().__init__()
        self.register_buffer("k", k.float())
        self.register_buffer("pose", world_from_camera.float())
        self.top_z = float(top_z)
        self.band = BAND
        self.cells = BEV_CELLS
        self.cell = BEV_CELL
        self.head = head

    def points(self, rgb: torch.Tensor, depth: torch.Tensor, valid: torch.Tensor) -> torch.Tensor:
        """World xy of the top-face pixels ``(N, 2)``."""
        r, g, b = rgb[0, 0], rgb[0, 1], rgb[0, 2]
        mask = (r > 0.24) & ((r - torch.maximum(g, b)) > 0.18) & (valid[0, 0] > 0.5)
        vu = torch.nonzero(mask)
        v, u = vu[:, 0].float(), vu[:, 1].float()
        z = depth[0, 0][mask]
        cam = torch.stack(
            [(u - self.k[0, 2]) / self.k[0, 0] * z, (v - self.k[1, 2]) / self.k[1, 1] * z, z], 1
        )
        world = cam @ self.pose[:3, :3].T + self.pose[:3, 3]
        keep = torch.abs(world[:, 2] - self.top_z) < self.band
        return world[keep][:, :2]

    def forward(self, rgb: torch.Tensor, depth: torch.Tensor, valid: torch.Tensor) -> torch.Tensor:
        pts = self.points(rgb, depth, valid)
        if pts.shape[0] < 5:
            return torch.zeros(1, 6)
        centre = pts.mean(0)
        out = self.head(bev(pts, centre, self.cells, self.cell))[0]
        xy = centre + out[0:2] / 100.0
        theta = torch.atan2(out[3], out[2])
        return torch.cat([xy, theta.reshape(1), out[4:7]]).reshape(1, 6)
