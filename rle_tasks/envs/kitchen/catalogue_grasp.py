"""Physical properties of catalogue instances: mass, size and the reference grasp planner's grasp in the
category's grasp mode (``catalogue.yaml``: ``grasp``), from the collision geometry. Body frame, SI units.

Modes (the Panda gripper pointing down, fingers closing along a horizontal axis):

- ``top`` (family 01's ``pick``): over the box centre, closing across the narrower horizontal side, the
  tool ``PALM`` below the top (``PALM_ROUND`` for round objects), at least ``FINGER_CLEARANCE`` above the
  support, the gripper fully open before closing;
- ``flat``: ``top`` for packs lying flat lower than ``FINGER_CLEARANCE``: the tool ``FLAT_HEIGHT`` above
  the support, so the pads' lower edges stay ``POSITION_TOL`` + 1 mm above it;
- ``rim``: for open receivers and mugs (as family 02's harness grips a bowl): the fingers straddle the
  outermost wall on a line from the centre of mass, ``RIM_DEPTH`` below the top, closing along that line
  across it from an opening ``RIM_GAP`` wider than the wall on each side; the line is the first of
  +-(narrower axis), +-(longer axis) where the wall is at most ``RIM_MAX_WALL`` thick, has free space
  inside it and both finger columns are free down to the pads, at the
  deepest tool height below the strip's own top (raised by ``RIM_RAISE`` steps while the pads still meet
  ``MIN_CONTACT`` of it) where one is;
- ``handle``: ``top`` at a handle: along the longer axis from its far ends inwards, the first strip whose
  cross-section at the pads fits the opening, the tool ``PALM`` below the strip's own top.

``graspable``: ``top``, ``flat`` and ``handle``: the grasped band lies within ``GRASP_REACH`` of the
grasp point on either side and is at least ``EMPTY`` wide (the closed hand's empty test, ``held``), and
the pads meet at least ``MIN_CONTACT`` of the object's height; ``rim``: a line as above exists (its
empty test is ``RIM_HELD``: walls are thinner than ``EMPTY``).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import mujoco
import numpy as np

from rle_tasks.envs.kitchen import catalogue_solid as solid
from rle_tasks.envs.kitchen.catalogue_data import CATEGORIES, instance
from rle_tasks.envs.kitchen.catalogue_geometry import add_geoms
from rle_tasks.envs.kitchen.catalogue_mass import target_mass

GRIPPER_OPENING = 0.08
"""Panda gripper's full opening [m]."""
POSITION_TOL = 0.005
"""The grasp planner's positioning tolerance before it closes (``pick``'s final ``tol``) [m]."""
GRASP_REACH = GRIPPER_OPENING / 2 - POSITION_TOL
"""Farthest the grasped band may reach from the grasp point along the closing axis [m]."""
PALM = 0.016
"""Grasp depth below the top [m] (``pick.PALM``)."""
PALM_ROUND = 0.03
"""Grasp depth below a round object's top [m] (``pick.PALM_ROUND``)."""
ROUND = 0.008
"""Spread of the half extents below which an object counts as round [m] (``pick.ROUND``)."""
FINGER_CLEARANCE = 0.022
"""Least height of the tool above the support [m] (``pick.FINGER_CLEARANCE``)."""
EMPTY = 0.01
"""Finger opening below which the closed hand holds nothing [m] (``pick.EMPTY``)."""
PAD_HALF_HEIGHT = 0.008
"""Half height of the Panda gripper's finger pads [m] (robosuite ``panda_gripper.xml``)."""
PAD_HALF_WIDTH = 0.008
"""Half width of the pads across the closing axis [m] (robosuite ``panda_gripper.xml``)."""
PAD_TIP = 0.0044
"""Pads' lower edge below the tool point (``grip_site``) [m]: pads at 0.0934 m +- 0.008 m from the hand,
the grip site at 0.097 m."""
FINGER_THICKNESS = 0.02
"""Extent of a finger along the closing axis, pad included, kept free of the object [m]."""
FINGER_HALF_WIDTH = 0.011
"""Half width of a finger across the closing axis [m]."""
FLAT_HEIGHT = PAD_TIP + POSITION_TOL + 0.001
"""Tool height above the support in ``flat`` mode [m]: the pads' lower edge 1 mm more than the
positioning tolerance above it."""
RIM_DEPTH = 0.02
"""Tool depth below the top in ``rim`` mode [m] (family 02's ``RIM_DEPTH``)."""
RIM_GAP = 0.011
"""Free space between a pad and the wall on each side before closing in ``rim`` mode [m] (family 02's
0.028 m opening over a 6 mm wall: (0.028 - 0.006) / 2)."""
RIM_HELD = 0.003
"""Finger opening above which a rim grasp holds the wall [m]: the closed empty hand reads 0.0020 m (the
pads meet), the thinnest wall held in the lift test 0.0040 m (the white bowl's); 0.003 m lies between."""
RIM_RAISE = 0.002
"""Step by which a rim grasp is raised when the fingers do not fit at ``RIM_DEPTH`` [m] (a plate's floor
lies under the inner finger)."""
RIM_MAX_WALL = 0.02
"""Widest wall a rim grasp pinches, across the pads' band [m]: wider is a slanted shelf that vertical pads
squeeze out rather than hold (the plate's rim, 25-31 mm: the lift test holds it on 1 side of 4, at 2
of 4 heights; the walls that lift are 5-15 mm)."""
MIN_CONTACT = 0.006
"""Least height of the object (in ``rim`` mode: of the strip's wall) the pads must meet [m]: 3/8 of their
16 mm; the graspable ``top`` and ``flat`` objects meet 9.8 mm (the pudding box) or more."""
HANDLE_STEP = 0.005
"""Step of the handle search along the longer axis [m]."""

MODES = ("top", "flat", "rim", "handle")


@dataclass(frozen=True)
class Properties:
    """What the catalogue derives for an instance (SI units, body frame).

    Attributes:
        mass: Mass [kg] (``catalogue_mass.target_mass``).
        center: Centre of the box around the collision geometry [m].
        half: Half extents of that box [m].
        mode: Grasp mode of its category.
        point: Tool point of the grasp [m].
        axis: Closing direction, a unit (x, y).
        opening: Finger opening before closing [m].
        grasp_height: Height of the tool above the object's lowest point [m].
        band: (low, high) of the geometry along ``axis`` in the pads' band, relative to ``point`` [m].
        width: Extent of that band [m] (``band[1] - band[0]``).
        held: Finger opening above which the closed hand holds the object [m].
        graspable: Fits the mode's grasp (see the module docstring).
    """

    mass: float
    center: tuple[float, float, float]
    half: tuple[float, float, float]
    mode: str
    point: tuple[float, float, float]
    axis: tuple[float, float]
    opening: float
    grasp_height: float
    band: tuple[float, float]
    width: float
    held: float
    graspable: bool

    @property
    def size(self) -> tuple[float, float, float]:
        """Full extents of the bounding box [m]."""
        return tuple(2 * h for h in self.half)


@dataclass(frozen=True)
class _Grasp:
    point: np.ndarray
    axis: np.ndarray
    opening: float
    band: tuple[float, float]
    held: float
    ok: bool


def probe(instance_id: str, density: float | None = None) -> tuple[mujoco.MjModel, mujoco.MjData]:
    """The instance alone as a free body (collision geoms only; ``density`` [kg/m^3] for every geom, or
    the source's)."""
    spec = mujoco.MjSpec()
    body = spec.worldbody.add_body(name="probe")
    body.add_freejoint()
    add_geoms(body, spec, "probe", instance(instance_id), visual=False, density=density)
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return model, data


def _pads(z_tool: float) -> tuple[float, float]:
    return z_tool - PAD_TIP, z_tool - PAD_TIP + 2 * PAD_HALF_HEIGHT


def _top(iid: str, lo, hi, center, half, clearance: float) -> _Grasp:
    axis = 0 if half[0] <= half[1] else 1
    depth = PALM_ROUND if float(np.ptp(half)) < ROUND else PALM
    z_tool = max(hi[2] - depth, lo[2] + clearance)
    pts = solid.slab(iid, *_pads(z_tool))
    u = np.eye(2)[axis]
    point = np.array([center[0], center[1], z_tool])
    if not len(pts):
        return _Grasp(point, u, GRIPPER_OPENING, (0.0, 0.0), EMPTY, False)
    band = (float(pts[:, axis].min() - center[axis]), float(pts[:, axis].max() - center[axis]))
    ok = max(-band[0], band[1]) <= GRASP_REACH and band[1] - band[0] >= EMPTY
    return _Grasp(point, u, GRIPPER_OPENING, band, EMPTY, ok)


def _free(iid: str, origin, u, s_lo: float, s_hi: float, z_lo: float, z_hi: float) -> bool:
    """Whether the finger column s_lo..s_hi along ``u`` from ``origin``, z_lo..z_hi, is empty."""
    s = np.arange(s_lo, s_hi + 1e-9, solid.STEP * 2)
    z = np.arange(z_lo, z_hi + 1e-9, 0.002)
    return not solid.profile(iid, origin, u, s, FINGER_HALF_WIDTH, z).any()


def _rim_at(iid: str, z_tool: float, origin, u, s, hi) -> _Grasp:
    """The rim grasp across the outermost wall along ``u`` at tool height ``z_tool``."""
    z_lo, z_hi = _pads(z_tool)
    occ = solid.profile(iid, origin, u, s, PAD_HALF_WIDTH, np.arange(z_lo, z_hi + 1e-9, 0.002))
    if not occ.any():
        return _Grasp(np.array([*origin, z_tool]), u, GRIPPER_OPENING, (0.0, 0.0), RIM_HELD, False)
    k_out = int(np.nonzero(occ)[0].max())
    k_in = k_out
    while k_in > 0 and occ[k_in - 1]:
        k_in -= 1
    wall = float(s[k_out] - s[k_in]) + solid.STEP
    mid = float(s[k_in] + s[k_out]) / 2
    opening = wall + 2 * RIM_GAP
    ok = (
        wall <= RIM_MAX_WALL
        and k_in > 0
        and _free(iid, origin, u, mid - opening / 2 - FINGER_THICKNESS, mid - opening / 2, z_lo, hi[2] + 0.01)
        and _free(iid, origin, u, mid + opening / 2, mid + opening / 2 + FINGER_THICKNESS, z_lo, hi[2] + 0.01)
    )
    point = np.array([*(origin + mid * u), z_tool])
    return _Grasp(point, u, min(opening, GRIPPER_OPENING), (-wall / 2, wall / 2), RIM_HELD, ok)


def _rim(iid: str, lo, hi, center, half, com) -> _Grasp:
    origin = np.asarray(com[:2])
    narrow = 0 if half[0] <= half[1] else 1
    dirs = [np.eye(2)[narrow], -np.eye(2)[narrow], np.eye(2)[1 - narrow], -np.eye(2)[1 - narrow]]
    reach = float(np.linalg.norm(half[:2]) + np.linalg.norm(origin - center[:2])) + 0.01
    s = np.arange(0.0, reach, solid.STEP)
    z_all = np.arange(lo[2], hi[2] + 1e-9, 0.002)
    tops = []  # each strip's own top (a tray's side wall, not its end handles)
    for u in dirs:
        rows = np.nonzero(
            solid.profile(iid, origin, u, s, PAD_HALF_WIDTH, z_all, by_height=True).any(axis=0)
        )[0]
        tops.append(float(z_all[rows.max()]) if len(rows) else None)
    first = None
    for depth in np.arange(RIM_DEPTH, 0.0, -RIM_RAISE):  # deepest first
        for u, top in zip(dirs, tops):
            if top is None:
                continue
            z_tool = max(top - depth, lo[2] + FLAT_HEIGHT)
            if _pads(z_tool)[0] > top - MIN_CONTACT:
                continue
            grasp = _rim_at(iid, z_tool, origin, u, s, hi)
            if grasp.ok:
                return grasp
            first = first or grasp
    return first or _Grasp(np.array([*origin, hi[2]]), dirs[0], GRIPPER_OPENING, (0.0, 0.0), RIM_HELD, False)


def _handle(iid: str, lo, hi, center, half) -> _Grasp:
    long = 1 if half[0] <= half[1] else 0
    w = np.eye(2)[long]  # along the handle
    u = np.eye(2)[1 - long]  # closing axis, across it
    across = np.arange(-half[1 - long] - 0.005, half[1 - long] + 0.005, solid.STEP)
    z_all = np.arange(lo[2], hi[2] + 1e-9, 0.002)
    first = None
    for sign in (1.0, -1.0):
        for s in np.arange(half[long] - PAD_HALF_WIDTH, 0.0, -HANDLE_STEP):
            origin = center[:2] + sign * s * w
            occ = solid.profile(iid, origin, u, across, PAD_HALF_WIDTH, z_all, by_height=True)
            rows = np.nonzero(occ.any(axis=0))[0]
            if not len(rows):
                continue
            top = float(z_all[rows.max()])
            z_tool = max(top - PALM, lo[2] + FINGER_CLEARANCE)
            band_occ = solid.profile(iid, origin, u, across, PAD_HALF_WIDTH, np.arange(*_pads(z_tool), 0.002))
            if not band_occ.any():
                continue
            a_lo, a_hi = float(across[band_occ].min()), float(across[band_occ].max()) + solid.STEP
            mid = (a_lo + a_hi) / 2
            band = (a_lo - mid, a_hi - mid)
            point = np.array([*(origin + mid * u), z_tool])
            ok = band[1] <= GRASP_REACH and band[1] - band[0] >= EMPTY
            grasp = _Grasp(point, u, GRIPPER_OPENING, band, EMPTY, ok)
            if ok:
                return grasp
            first = first or grasp
    return first or _Grasp(np.array([*center[:2], hi[2]]), u, GRIPPER_OPENING, (0.0, 0.0), EMPTY, False)


@functools.cache
def properties(instance_id: str) -> Properties:
    """Mass, bounding box and grasp of an instance (see the module docstring)."""
    model, data = probe(instance_id)
    verts = np.concatenate([np.asarray(m.vertices) for m in solid.meshes(instance_id)])
    lo, hi = verts.min(axis=0), verts.max(axis=0)
    center, half = (lo + hi) / 2, (hi - lo) / 2
    mode = CATEGORIES[instance(instance_id).category].grasp
    if mode == "top":
        g = _top(instance_id, lo, hi, center, half, FINGER_CLEARANCE)
    elif mode == "flat":
        g = _top(instance_id, lo, hi, center, half, FLAT_HEIGHT)
    elif mode == "rim":
        g = _rim(instance_id, lo, hi, center, half, data.xipos[1])
    elif mode == "handle":
        g = _handle(instance_id, lo, hi, center, half)
    else:
        raise ValueError(f"{instance_id}: unknown grasp mode '{mode}'")
    p_lo, p_hi = _pads(float(g.point[2]))
    overlap = min(p_hi, hi[2]) - max(p_lo, lo[2])
    return Properties(
        mass=target_mass(instance_id),
        center=tuple(float(v) for v in center),
        half=tuple(float(v) for v in half),
        mode=mode,
        point=tuple(float(v) for v in g.point),
        axis=tuple(float(v) for v in g.axis),
        opening=float(g.opening),
        grasp_height=float(g.point[2] - lo[2]),
        band=tuple(float(v) for v in g.band),
        width=float(g.band[1] - g.band[0]),
        held=float(g.held),
        graspable=bool(g.ok and (mode in ("rim", "handle") or overlap >= MIN_CONTACT)),
    )
