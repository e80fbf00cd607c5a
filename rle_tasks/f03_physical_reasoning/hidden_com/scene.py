"""Sealed boxes with hidden ballast for ``03-hidden-com``, built with ``MjSpec``.

A box is one free body: an opaque shell (a solid box geom of mass ``shell_mass``, uniform) and a
ballast block (mass ``ballast_mass``) centred in one quadrant of the box at ``(+-q, +-q)`` in the box
frame, inside the shell, invisible and without collision. Quadrants are named counter-clockwise
seen from above, in the box frame (x to the red stripe, y to the left of it):

| quadrant | x | y |
|---|---|---|
| A | + | + |
| B | - | + |
| C | - | - |
| D | + | - |

The top carries four corner patches (A red, B green, C blue, D yellow) and the +x side face a red
stripe, so every quadrant is identifiable in RGB; they are massless.

Centre of mass in the box frame: ``r_c = ballast_mass r_b / (shell_mass + ballast_mass)``. Lifting
one bottom edge (force F up at ``x_F``, the box pivoting on the opposite bottom edge ``x_p``) needs
``F = m g (x_c - x_p) / (x_F - x_p)`` (moments about the pivot edge).
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from rle_design.errors import ConfigError

QUADRANTS = ("A", "B", "C", "D")
QUADRANT_SIGNS: dict[str, tuple[float, float]] = {"A": (1, 1), "B": (-1, 1), "C": (-1, -1), "D": (1, -1)}
_PATCH_RGBA = {
    "A": (0.9, 0.1, 0.1, 1),
    "B": (0.1, 0.75, 0.2, 1),
    "C": (0.15, 0.3, 0.95, 1),
    "D": (0.95, 0.85, 0.1, 1),
}


def box_name(i: int) -> str:
    """Body name of box ``i`` (0..2); its shell geom carries the same name."""
    return f"box_{i}"


@dataclass(frozen=True)
class BoxParams:
    """One sealed box (SI units).

    Attributes:
        half: Shell half extents (x, y, z) [m]; 70 mm across fits the Panda gripper (80 mm).
        shell_mass: Shell mass, uniform [kg].
        ballast_mass: Ballast mass [kg].
        ballast_offset: q: the ballast centre sits at (+-q, +-q, 0) in the box frame [m].
        ballast_half: Ballast half side (a cube) [m].
        quadrant: "A".."D" (secret).
    """

    half: tuple[float, float, float] = (0.035, 0.035, 0.04)
    shell_mass: float = 0.2
    ballast_mass: float = 0.4
    ballast_offset: float = 0.018
    ballast_half: float = 0.015
    quadrant: str = "A"

    def __post_init__(self) -> None:
        if self.quadrant not in QUADRANTS:
            raise ConfigError(
                f"BoxParams.quadrant must be one of {', '.join(QUADRANTS)}, got {self.quadrant!r}",
                code="f03.box_quadrant",
            )
        if self.ballast_offset + self.ballast_half > min(self.half[:2]):
            raise ConfigError(
                f"BoxParams: the ballast (offset {self.ballast_offset} m + half side {self.ballast_half} m) must fit "
                f"inside the shell (half width {min(self.half[:2])} m)",
                code="f03.box_ballast",
            )

    @property
    def mass(self) -> float:
        """Total mass m [kg]."""
        return self.shell_mass + self.ballast_mass

    @property
    def ballast_pos(self) -> np.ndarray:
        """Ballast centre in the box frame [m]."""
        sx, sy = QUADRANT_SIGNS[self.quadrant]
        return np.array([sx * self.ballast_offset, sy * self.ballast_offset, 0.0])

    @property
    def com(self) -> np.ndarray:
        """Centre of mass in the box frame, r_c = m_b r_b / (m_s + m_b) [m]."""
        return self.ballast_mass * self.ballast_pos / self.mass

    def edge_lift_force(self, axis: int, sign: float, g: float = 9.81) -> float:
        """Force [N] that starts lifting the bottom edge at ``sign * half[axis]`` (pivot: the opposite edge).

        ``F = m g (x_c - x_p) / (x_F - x_p)`` with ``x_F = sign * half``, ``x_p = -sign * half`` along
        ``axis``: moments about the pivot edge, the force in the plane of the centre of mass normal to
        the edge.
        """
        x_f, x_p = sign * self.half[axis], -sign * self.half[axis]
        return self.mass * g * (self.com[axis] - x_p) / (x_f - x_p)


def add_box(
    spec: mujoco.MjSpec, name: str, params: BoxParams, pos: tuple[float, float, float], yaw: float = 0.0
) -> mujoco.MjsBody:
    """Add a sealed box body ``name`` resting at ``pos`` (bottom centre) with heading ``yaw`` [rad]."""
    hx, hy, hz = params.half
    body = spec.worldbody.add_body()
    body.name = name
    body.pos = np.asarray(pos, dtype=float) + np.array([0.0, 0.0, hz])
    body.quat = np.array([np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2)])
    free = body.add_freejoint()
    free.name = name
    shell = body.add_geom()
    shell.name = name
    shell.type = mujoco.mjtGeom.mjGEOM_BOX
    shell.size = np.array(params.half)
    shell.mass = params.shell_mass
    shell.rgba = np.array([0.8, 0.78, 0.72, 1.0])
    shell.friction = np.array([0.8, 0.005, 0.0001])
    shell.condim = 4
    ballast = body.add_geom()
    ballast.name = f"{name}_ballast"
    ballast.type = mujoco.mjtGeom.mjGEOM_BOX
    ballast.size = np.full(3, params.ballast_half)
    ballast.pos = params.ballast_pos
    ballast.mass = params.ballast_mass
    ballast.contype = 0
    ballast.conaffinity = 0
    ballast.group = 5
    ballast.rgba = np.array([0.0, 0.0, 0.0, 0.0])
    marks = [(f"{name}_stripe", (0.001, hy * 0.6, hz * 0.3), (hx + 0.001, 0, 0), _PATCH_RGBA["A"])]
    for quad, (sx, sy) in QUADRANT_SIGNS.items():
        marks.append(
            (
                f"{name}_patch_{quad}",
                (0.012, 0.012, 0.001),
                (sx * (hx - 0.015), sy * (hy - 0.015), hz + 0.001),
                _PATCH_RGBA[quad],
            )
        )
    for mark_name, half, mpos, rgba in marks:
        g = body.add_geom()
        g.name = mark_name
        g.type = mujoco.mjtGeom.mjGEOM_BOX
        g.size = np.array(half)
        g.pos = np.array(mpos)
        g.rgba = np.array(rgba)
        g.mass = 0.0
        g.density = 0.0
        g.contype = 0
        g.conaffinity = 0
    return body
