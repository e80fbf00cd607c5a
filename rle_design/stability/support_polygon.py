"""Support polygon of ground contacts and the static stability margin (McGhee & Frank, 1968).

The support polygon is the convex hull of the ground-contact points projected on the horizontal
plane. The static stability margin (SSM) is the smallest signed distance from the projection of the
centre of mass to the polygon's edge lines: positive inside, negative outside, zero on an edge.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rle_design.errors import RleError

__all__ = ["SupportPolygon", "convex_hull", "static_margin", "support_polygon"]


class StabilityError(RleError):
    """A stability quantity is undefined for the given input (e.g. fewer than 3 contacts)."""

    code = "stability.invalid"


def _cross(o: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    return float((a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]))


def convex_hull(points: np.ndarray) -> np.ndarray:
    """Convex hull of 2-D points, counter-clockwise, without collinear points (monotone chain).

    Args:
        points: (n, 2) or (n, 3) points [m]; a third column is ignored.

    Returns:
        (m, 2) hull vertices in counter-clockwise order.
    """
    pts = np.asarray(points, dtype=float)
    if pts.ndim != 2 or pts.shape[1] < 2:
        raise StabilityError(f"points must have shape (n, 2) or (n, 3), got {pts.shape}")
    pts = np.unique(np.round(pts[:, :2], 12), axis=0)
    if len(pts) < 3:
        return pts
    lower: list[np.ndarray] = []
    for p in pts:
        while len(lower) >= 2 and _cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    upper: list[np.ndarray] = []
    for p in pts[::-1]:
        while len(upper) >= 2 and _cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return np.array(lower[:-1] + upper[:-1])


@dataclass(frozen=True)
class SupportPolygon:
    """Convex support polygon in the horizontal plane.

    Attributes:
        vertices: (m, 2) counter-clockwise vertices [m].
    """

    vertices: np.ndarray

    @property
    def area(self) -> float:
        """Polygon area [m^2] (shoelace formula)."""
        v = self.vertices
        if len(v) < 3:
            return 0.0
        x, y = v[:, 0], v[:, 1]
        return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))

    def edges(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """(start, end) vertex pairs in counter-clockwise order."""
        v = self.vertices
        return [(v[i], v[(i + 1) % len(v)]) for i in range(len(v))]

    def edge_distances(self, point: np.ndarray) -> np.ndarray:
        """Signed distance of ``point`` (x, y) to every edge line [m]; positive on the inner side."""
        p = np.asarray(point, dtype=float)[:2]
        out = []
        for a, b in self.edges():
            e = b - a
            n_in = np.array([-e[1], e[0]]) / np.linalg.norm(e)  # left of a CCW edge is inside
            out.append(float(np.dot(p - a, n_in)))
        return np.array(out)


def support_polygon(points: np.ndarray) -> SupportPolygon:
    """Support polygon of contact points (n, 2|3) [m].

    Raises:
        StabilityError: Fewer than three non-collinear points (no area to stand on).
    """
    hull = convex_hull(points)
    if len(hull) < 3:
        raise StabilityError(
            f"a support polygon needs at least 3 non-collinear contact points, got {len(hull)}",
            code="stability.degenerate_support",
        )
    return SupportPolygon(hull)


def static_margin(polygon: SupportPolygon, com: np.ndarray) -> float:
    """Static stability margin: min signed distance of the COM projection to the edges [m].

    Args:
        polygon: Support polygon.
        com: Centre of mass (x, y[, z]) [m]; only x and y are used.

    Returns:
        Positive inside the polygon (distance to the nearest edge), negative outside.
    """
    return float(np.min(polygon.edge_distances(com)))
