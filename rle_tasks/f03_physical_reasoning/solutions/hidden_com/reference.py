"""Reference agent of ``03-hidden-com``: wrist-torque probing through the controller's pose error.

Uses only what the agent gets: the published box centres and top-camera geometry (instruction), the
top RGB view and the arm's state; every motion is an ordinary metered action.

Per box:

1. grasp it at its centre from above (fingers along world y) and lift it 10 mm; the ballast's
   offset ``c`` (world, horizontal) loads the wrist with the torque ``m g (-c_y, c_x)``, which the
   operational-space controller's finite stiffness shows as an orientation error ``e`` between the
   target and the measured tool pose (about 1 mrad for 12 mm of offset);
2. put it down turned by -90 deg, regrasp and measure again, four times: with the box turned by
   k quarter turns, ``e_k = b + K (c_k,y, -c_k,x)`` where ``b`` (the posture's own error, the grasp's
   small offsets) does not turn with the box; ``c`` = (1/4) sum_k R(k 90 deg) (-e_k,y, e_k,x)
   removes ``b`` exactly;
3. the quadrant is the colour of the corner patch that lies in the direction of ``c`` from the box's
   centre in the top view taken before the first grasp (red A, green B, blue C, yellow D); answer it.

Run it in a workspace with ``python reference.py`` (it connects, answers and seals).
"""

from __future__ import annotations

from typing import Any

import mujoco
import numpy as np

from rle_design.control import CartesianHelper, orientation_error
from rle_design.control.layout import ACTION_SIZE, BASE, GRIPPER, MODE, TORSO

BOX_XY = ((0.30, -0.20), (0.36, 0.0), (0.30, 0.20))
"""Published box centres [m]."""
TABLE_Z = 0.75
BOX_H = 0.08
PATCH = 0.023
"""Distance of a corner patch's centre from the box axis, per horizontal axis [m]."""
TOP_CAMERA = (np.array([0.30, 0.0, 1.80]), 50.0)
"""Published top camera: position [m] and vertical field of view [deg]; looks down, image up = +x."""
GRIP_Z = TABLE_Z + BOX_H - 0.025
LIFT = 0.01
HOLD = 30
BOX_CODES = (-1.0, 0.0, 1.0)
QUADRANT_CODES = {"A": -0.75, "B": -0.25, "C": 0.25, "D": 0.75}


def _turn(quat: np.ndarray, angle: float) -> np.ndarray:
    r = np.array([np.cos(angle / 2), 0.0, 0.0, np.sin(angle / 2)])
    out = np.zeros(4)
    mujoco.mju_mulQuat(out, r, quat)
    return out


def top_pixel(point: np.ndarray, size: tuple[int, int]) -> tuple[int, int]:
    """(row, col) of a world point in the published top view (pinhole)."""
    pos, fovy = TOP_CAMERA
    h, w = size
    f = (h / 2) / np.tan(np.radians(fovy / 2))
    depth = pos[2] - point[2]
    return int(round(h / 2 - f * (point[0] - pos[0]) / depth)), int(
        round(w / 2 - f * (point[1] - pos[1]) / depth)
    )


def patch_colour(image: np.ndarray, point: np.ndarray) -> str:
    """Quadrant letter of the patch colour at ``point`` (3 x 3 pixels): yellow when red and green both
    exceed 0.75 of the brightest channel and blue does not, else the brightest channel (red, green, blue)."""
    r, c = top_pixel(point, image.shape[:2])
    px = image[r - 1 : r + 2, c - 1 : c + 2].reshape(-1, 3).mean(axis=0)
    px = px / max(float(px.max()), 1e-6)
    if px[0] > 0.75 and px[1] > 0.75 and px[2] < 0.75:
        return "D"
    return "ABC"[int(np.argmax(px))]


class Prober:
    """The probing motions on one session."""

    def __init__(self, env: Any) -> None:
        self.env = env
        obs = env.reset()
        self.image = np.asarray(obs["rgb"]["top"])
        self.helper = CartesianHelper(env.step, obs)
        self.down = np.asarray(obs["arms"][0]["ee_quat"], dtype=float)

    def _move(self, pos, quat, speed: float = 0.5) -> None:
        self.helper.move_to(np.asarray(pos, dtype=float), quat, speed=speed, tol_pos=0.002, tol_rot=0.01)

    def _error(self) -> np.ndarray:
        s = self.helper.state
        return orientation_error(np.asarray(s["target_quat"]), np.asarray(s["ee_quat"]))

    def measure(self, x: float, y: float) -> np.ndarray:
        self._move([x, y, GRIP_Z], self.down)
        self.helper.grasp(15)
        self._move([x, y, GRIP_Z + LIFT], self.down)
        self.helper.wait(HOLD)
        return self._error()

    def quarter_turn(self, x: float, y: float) -> None:
        turned = _turn(self.down, -np.pi / 2)
        self._move([x, y, GRIP_Z + LIFT], turned)
        self._move([x, y, GRIP_Z + 0.001], turned)
        self.helper.release(10)
        self._move([x, y, TABLE_Z + BOX_H + 0.03], turned)
        self._move([x, y, TABLE_Z + BOX_H + 0.03], self.down)

    def offset(self, box: int) -> np.ndarray:
        """Direction of the ballast's offset, world frame, box as it stood at the start."""
        x, y = BOX_XY[box]
        self._move([x, y, TABLE_Z + BOX_H + 0.05], self.down, speed=1.0)
        total = np.zeros(2)
        for k in range(4):
            if k:
                self.quarter_turn(x, y)
            e = self.measure(x, y)
            v = np.array([-e[1], e[0]])  # ~ c_k + bias
            a = k * np.pi / 2  # c_k = R(-k 90 deg) c_0, so c_0 = R(k 90 deg) c_k
            total += np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]]) @ v
        self._move([x, y, GRIP_Z + 0.001], self.down)
        self.helper.release(10)
        self._move([x, y, TABLE_Z + BOX_H + 0.05], self.down, speed=1.0)
        return total / 4

    def answer(self, box: int, quadrant: str) -> None:
        a = np.zeros(ACTION_SIZE)
        a[GRIPPER] = self.helper.grip
        a[MODE] = 1.0
        a[BASE.start] = BOX_CODES[box]
        a[TORSO] = QUADRANT_CODES[quadrant]
        self.helper.obs = self.env.step(a)


def probe_and_answer(prober: Prober, box: int) -> str:
    """Probe ``box``, read the quadrant its ballast offset points to, answer it; returns the quadrant."""
    c = prober.offset(box)
    x, y = BOX_XY[box]
    corner = np.array([x + PATCH * np.sign(c[0]), y + PATCH * np.sign(c[1]), TABLE_Z + BOX_H])
    quadrant = patch_colour(prober.image, corner)
    prober.answer(box, quadrant)
    return quadrant


def solve(env: Any) -> tuple[str, ...]:
    """Probe and answer the three boxes; returns the answers."""
    prober = Prober(env)
    return tuple(probe_and_answer(prober, box) for box in range(3))


def main() -> None:
    from client import connect  # the workspace's client (written by `rle dev`)

    with connect() as env:
        print("answers:", solve(env))
        env.seal()


if __name__ == "__main__":
    main()
