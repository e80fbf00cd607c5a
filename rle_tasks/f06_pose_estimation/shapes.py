"""The three extruded blocks (verifier-side data: never copied into a workspace).

Each block is a union of axis-aligned boxes in its own frame, extruded ``HEIGHT`` up from the table.
Block frame: origin at the centroid of the footprint on the table plane (z = 0 of the table top),
z up, x to the right and y up in the drawings below; the planar pose ``(x, y, theta)`` is the
frame's origin [m] and its rotation about the world z axis [rad]. Dimensions follow Push-T's T (bar
120 x 30 mm, stem 30 x 90 mm) at 1 mm per pixel of the original.

    T (id 0)          C (id 1)          F (id 2)
    #####             ####              ####
      #               #                 #
      #               #                 ###
      #               ####              #
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

HEIGHT = 0.03
"""Extrusion height of every block [m]."""
NAMES = ("T", "C", "F")
"""Shape names by shape id (0, 1, 2)."""


@dataclass(frozen=True)
class Block:
    """One extruded block.

    Attributes:
        name: Letter.
        boxes: ``(centre_x, centre_y, half_x, half_y)`` per box in the drawing frame [m] (before the
            centroid shift).
    """

    name: str
    boxes: tuple[tuple[float, float, float, float], ...]

    @property
    def area(self) -> float:
        """Footprint area [m^2] (boxes do not overlap)."""
        return float(sum(4 * hx * hy for _, _, hx, hy in self.boxes))

    @property
    def centroid(self) -> np.ndarray:
        """Footprint centroid in the drawing frame [m]."""
        w = np.array([4 * hx * hy for _, _, hx, hy in self.boxes])
        c = np.array([(cx, cy) for cx, cy, _, _ in self.boxes])
        return (w[:, None] * c).sum(0) / w.sum()

    def boxes_in_frame(self) -> list[tuple[float, float, float, float]]:
        """Boxes with centres in the block frame (origin at the footprint centroid) [m]."""
        c = self.centroid
        return [(cx - c[0], cy - c[1], hx, hy) for cx, cy, hx, hy in self.boxes]

    def contains(self, points: np.ndarray) -> np.ndarray:
        """Whether block-frame points ``(N, 2)`` [m] lie inside the footprint."""
        p = np.atleast_2d(points)
        inside = np.zeros(len(p), bool)
        for cx, cy, hx, hy in self.boxes_in_frame():
            inside |= (np.abs(p[:, 0] - cx) <= hx) & (np.abs(p[:, 1] - cy) <= hy)
        return inside

    def radius(self) -> float:
        """Largest distance of a footprint corner from the origin [m]."""
        r = 0.0
        for cx, cy, hx, hy in self.boxes_in_frame():
            for sx in (-1, 1):
                for sy in (-1, 1):
                    r = max(r, float(np.hypot(cx + sx * hx, cy + sy * hy)))
        return r


BLOCKS: tuple[Block, ...] = (
    # T: bar 120 x 30 mm on top, stem 30 x 90 mm below it
    Block("T", ((0.0, 0.0, 0.06, 0.015), (0.0, -0.06, 0.015, 0.045))),
    # C: back 30 x 120 mm, two arms 60 x 30 mm to the right at top and bottom
    Block("C", ((0.0, 0.0, 0.015, 0.06), (0.045, 0.045, 0.03, 0.015), (0.045, -0.045, 0.03, 0.015))),
    # F: back 30 x 120 mm, top arm 75 x 30 mm, middle arm 45 x 30 mm
    Block("F", ((0.0, 0.0, 0.015, 0.06), (0.0525, 0.045, 0.0375, 0.015), (0.0375, 0.0, 0.0225, 0.015))),
)
"""The blocks by shape id."""
