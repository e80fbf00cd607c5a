"""Perception of fixtures: the open drawer (``FixtureViews.find_open_drawer``, mixed into
``skills.Skills``) and the open hinged cabinet door (``find_open_door``), from the segmenter's points
and depth."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .geometry import world_points
from .kitchen import DOOR_Y, FRONT_Y, LANE_Y, Drawer
from .perception import in_box
from .robot import CAMERAS

if TYPE_CHECKING:
    from .skills import Skills

__all__ = ["FixtureViews", "OpenDoor", "find_open_door"]


class FixtureViews:
    """Fixtures found in the views (methods of ``skills.Skills``)."""

    def find_open_drawer(self) -> Drawer | None:
        """The drawer that stands out of the run (its points over 0.15 m in front of ``FRONT_Y``: closed
        drawers' handles stand 0.066 m proud)."""
        lo, hi = (-np.inf, -np.inf, 0.6), (np.inf, FRONT_Y - 0.15, 0.95)
        for turn in (0.0, 0.8, -0.8):
            self.look(turn)
            pts = self.see("drawer", lo, hi)
            if len(pts) >= 20:
                break
        else:
            return None
        handle = self.see("drawer cabinet handle", lo, hi, tries=2)
        body = pts[np.linalg.norm(pts[:, :2] - np.median(pts[:, :2], axis=0), axis=1) < 0.6]
        x0, x1 = np.percentile(body[:, 0], [1, 99])
        width = float(min((0.5, 0.6, 0.7), key=lambda w: abs(w - (x1 - x0 + 0.02))))
        x = float(np.median(handle[:, 0])) if len(handle) >= 3 else float((x0 + x1) / 2)
        if abs((x1 - x0 + 0.02) - width) < 0.04:  # the whole front seen: its middle is the better centre
            x = float((x0 + x1) / 2)
        if len(handle) >= 3:
            front = float(np.median(handle[:, 1])) + 0.035
            hz = float(np.median(handle[:, 2]))
        else:
            front = float(np.percentile(body[:, 1], 2))
            hz = 0.78
        inner = in_box(
            body,
            (x - width / 2 + 0.05, front + 0.04, -np.inf),
            (x + width / 2 - 0.05, FRONT_Y - 0.05, np.inf),
        )
        floor = float(np.percentile(inner[:, 2], 5)) if len(inner) >= 10 else hz - 0.08
        d = Drawer(x, width, front, hz, floor, FRONT_Y - 0.021 - front)
        self.note(
            f"open drawer at x {x:.2f} width {width:.1f} front {front:.2f} floor {floor:.2f} handle z {hz:.2f}"
        )
        return d


@dataclass(frozen=True)
class OpenDoor:
    """An open hinged base-cabinet door seen by ``find_open_door``.

    Attributes:
        hinge: (x, y) of its hinge axis [m].
        along: Unit (x, y) from the hinge towards the free edge.
        out: Unit (x, y) normal of the face to push (away from its cabinet).
        length: Hinge to free edge [m].
        opened: Opening angle [rad] (0 closed).
        closing: +1 when closing turns the door counter-clockwise seen from above, else -1.
    """

    hinge: np.ndarray
    along: np.ndarray
    out: np.ndarray
    length: float
    opened: float
    closing: float


def _door_points(sk: Skills) -> np.ndarray:
    """Points [m] of cabinet doors standing out of the run (below the counter tops) in view now."""
    return sk.see("cabinet door", (-np.inf, -np.inf, 0.15), (np.inf, FRONT_Y - 0.12, 0.9), tries=2)


def _cabinet_side(sk: Skills, hinge: np.ndarray, along: np.ndarray, length: float) -> tuple[float, str]:
    """+1 when the door's cabinet lies on the +x side of the hinge, -1 on the -x side, with the evidence.

    The handle stands 3.5 cm proud of the door's outer face (away from the cabinet); failing a clear view of
    it, the open cabinet shows its interior (depth points well behind the fronts) on its side of the hinge,
    a closed neighbour its front."""
    normal = np.array([-along[1], along[0]])
    lo, hi = (-np.inf, -np.inf, 0.5), (np.inf, FRONT_Y - 0.1, 0.9)
    handle = sk.see("cabinet handle", lo, hi, tries=2)
    if len(handle):
        off = (handle[:, :2] - hinge) @ normal
        near = np.abs((handle[:, :2] - hinge) @ along - (length - 0.06)) < 0.12
        proud = off[near & (np.abs(off) > 0.012) & (np.abs(off) < 0.08)]
        if len(proud) >= 3 and abs(float(np.mean(np.sign(proud)))) > 0.5:
            out_sign = float(np.sign(np.median(proud)))
            return -float(np.sign(out_sign * normal[0])) or 1.0, f"handle ({len(proud)} points)"
    o = sk.obs
    pts = np.concatenate([world_points(o, cam) for cam in CAMERAS])
    pts = in_box(pts, (-np.inf, FRONT_Y + 0.05, 0.25), (np.inf, -0.05, 0.8))
    counts = {}
    for side in (1.0, -1.0):
        a, b = sorted((hinge[0] + side * 0.05, hinge[0] + side * (length - 0.05)))
        counts[side] = int(np.sum((pts[:, 0] > a) & (pts[:, 0] < b)))
    side = max(counts, key=counts.get)
    return side, f"interior {counts}"


def find_open_door(sk: Skills) -> OpenDoor | None:
    """The hinged base-cabinet door standing open: found from the look pose (turning), then seen from in
    front of it (base at ``LANE_Y``); its plane is the line through its points seen from above, the hinge
    where that line meets the run's front, the face to push the one away from its cabinet."""
    pts = np.zeros((0, 3))
    for turn in (0.0, 0.8, -0.8, 1.3, -1.3):
        sk.look(turn)
        pts = _door_points(sk)
        if len(pts) >= 30:
            break
    if len(pts) < 30:
        sk.note("no open cabinet door in sight")
        return None
    x0 = float(np.median(pts[:, 0]))
    sk.tuck()
    sk.goto(x0, LANE_Y, lane=True)
    views = [pts]
    for turn in (0.0, 0.5, -0.5):
        sk.look(turn)
        views.append(_door_points(sk))
    pts = np.concatenate(views)
    pts = pts[np.abs(pts[:, 0] - np.median(pts[:, 0])) < 0.7]
    xy = pts[:, :2]
    c = xy.mean(axis=0)
    w, v = np.linalg.eigh(np.cov((xy - c).T))
    along = v[:, 1] if v[1, 1] < 0 else -v[:, 1]  # towards the free edge (out of the run, -y)
    if abs(along[1]) < 0.2:
        sk.note(f"door points do not stand out of the run (direction {np.round(along, 2)})")
        return None
    hinge = c + along * (DOOR_Y - c[1]) / along[1]
    length = float(np.percentile((xy - hinge) @ along, 98))
    sk.look(0.0)
    side, why = _cabinet_side(sk, hinge, along, length)
    closed = np.array([side, 0.0])  # the closed door runs from the hinge across its cabinet
    opened = float(np.arccos(np.clip(along @ closed, -1.0, 1.0)))
    closing = float(np.sign(along[0] * closed[1] - along[1] * closed[0]))
    normal = np.array([-along[1], along[0]])
    out = normal if normal @ closed < 0 else -normal
    d = OpenDoor(hinge, along, out, length, opened, closing)
    sk.note(
        f"open door: hinge {np.round(hinge, 3)} along {np.round(along, 2)} length {length:.2f} opened {opened:.2f} "
        f"cabinet side {side:+.0f} ({why}), {len(pts)} points, spread {np.round(np.sqrt(w), 3)}"
    )
    return d
