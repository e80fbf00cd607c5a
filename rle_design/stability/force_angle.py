"""Force-angle stability measure (Papadopoulos & Rey, ICRA 1996).

For ground contacts p_1..p_n ordered counter-clockwise seen from above, each edge i is a tip-over
axis a_i = p_{i+1} - p_i. With f_r the net force acting on the centre of mass that is not supplied by
the ground (gravity plus d'Alembert inertial force, m (g - a)) and n_r the corresponding moment:

    l_i  = (I - a^ a^T)(p_{i+1} - p_c)            axis normal through the COM
    f_i  = (I - a^ a^T) f_r,  n_i = (a^ a^T) n_r
    f*_i = f_i + (l^_i x n_i) / |l_i|             equivalent force
    theta_i = sigma_i arccos(f^*_i . l^_i),  sigma_i = +1 if (f^*_i x l^_i) . a^_i < 0 else -1
    d_i  = -l_i + (l_i . f^*_i) f^*_i              moment arm of f* about the axis
    beta_i = theta_i |d_i| |f*_i|                  (N m rad)

The measure is beta = min_i beta_i; beta <= 0 means tip-over about that axis. ``theta`` (the angle
alone) is reported as well: it reaches zero exactly when the net force passes through an axis.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rle_design.stability.support_polygon import StabilityError, convex_hull

__all__ = ["ForceAngle", "force_angle"]


@dataclass(frozen=True)
class ForceAngle:
    """Force-angle measure about every tip-over axis.

    Attributes:
        beta: Per-axis measure theta |d| |f*| [N m rad].
        theta: Per-axis signed angle [rad].
        axes: (m, 2, 3) axis end points [m].
    """

    beta: np.ndarray
    theta: np.ndarray
    axes: np.ndarray

    @property
    def min_beta(self) -> float:
        """Smallest measure [N m rad]; <= 0 tips."""
        return float(np.min(self.beta))

    @property
    def min_theta(self) -> float:
        """Smallest signed angle [rad]; <= 0 tips."""
        return float(np.min(self.theta))

    @property
    def critical_axis(self) -> int:
        return int(np.argmin(self.beta))


def _unit(v: np.ndarray) -> np.ndarray:
    n = float(np.linalg.norm(v))
    return v / n if n > 1e-12 else v * 0.0


def force_angle(
    contacts: np.ndarray,
    com: np.ndarray,
    mass: float,
    gravity: tuple[float, float, float] = (0.0, 0.0, -9.81),
    accel: np.ndarray | None = None,
    moment: np.ndarray | None = None,
) -> ForceAngle:
    """Force-angle stability of a body on ground contacts.

    Args:
        contacts: (n, 3) ground-contact points [m]; hull order is computed here.
        com: Centre of mass (3,) [m].
        mass: Total mass [kg].
        gravity: Gravity vector [m/s^2].
        accel: COM acceleration (3,) [m/s^2]; its d'Alembert force -m a joins gravity.
        moment: Net moment about the COM not supplied by the ground (3,) [N m].
    """
    pts = np.asarray(contacts, dtype=float)
    if pts.ndim != 2 or pts.shape[1] != 3:
        raise StabilityError(f"contacts must have shape (n, 3), got {pts.shape}")
    hull2 = convex_hull(pts)
    if len(hull2) < 3:
        raise StabilityError(
            f"force-angle needs at least 3 non-collinear contacts, got {len(hull2)}",
            code="stability.degenerate_support",
        )
    # Recover the heights of the hull vertices from the nearest input point.
    z = [pts[np.argmin(np.linalg.norm(pts[:, :2] - h, axis=1)), 2] for h in hull2]
    hull = np.column_stack([hull2, z])
    pc = np.asarray(com, dtype=float)
    f_r = mass * (np.asarray(gravity, dtype=float) - (np.zeros(3) if accel is None else np.asarray(accel)))
    n_r = np.zeros(3) if moment is None else np.asarray(moment, dtype=float)
    betas, thetas, axes = [], [], []
    for i in range(len(hull)):
        p0, p1 = hull[i], hull[(i + 1) % len(hull)]
        a = _unit(p1 - p0)
        proj = np.eye(3) - np.outer(a, a)
        l = proj @ (p1 - pc)
        f = proj @ f_r
        n = np.outer(a, a) @ n_r
        ln = float(np.linalg.norm(l))
        l_hat = _unit(l)
        f_star = f + (np.cross(l_hat, n) / ln if ln > 1e-12 else 0.0)
        f_hat = _unit(f_star)
        sigma = 1.0 if float(np.dot(np.cross(f_hat, l_hat), a)) < 0 else -1.0
        theta = sigma * float(np.arccos(np.clip(np.dot(f_hat, l_hat), -1.0, 1.0)))
        d = -l + float(np.dot(l, f_hat)) * f_hat
        betas.append(theta * float(np.linalg.norm(d)) * float(np.linalg.norm(f_star)))
        thetas.append(theta)
        axes.append([p0, p1])
    return ForceAngle(np.array(betas), np.array(thetas), np.array(axes))
