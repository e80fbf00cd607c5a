"""Build-time: the fastened reference leaders re-balanced with their rods and posts counted.

The ideal spring becomes a catalog spring (``rle_design/catalogs/springs.yaml``, ``catalog_spring``):
the entry whose rate is nearest the exact stiffness among those rated for ``FORCE_MARGIN`` times the
largest tension over the grid. With brackets and rods in place, the counterweight masses and
centres (within ``BOX`` of the exact placement) and the spring's attachment point (within
``ATTACH_BOX``; the catalog rate is fixed, so k a b = M g d is met by b) are re-optimised over the
public workspace grid with the co-design optimiser (``rle_design.kinematics.codesign``,
CasADi/IPOPT), which counts each rod's mass at its midpoint (``optimise``).
"""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np

from rle_design.kinematics import model_from_mujoco
from rle_design.kinematics.codesign import CounterweightSlot, SpringSlot, optimise_balance
from rle_tasks.f09_gello.solutions.attached import ARM_RADIUS, ROD_DENSITY, Fastened, write_leader

BOX = 0.015
"""Half-width of the square (across the joint axis; the axial height stays) around each exact
counterweight centre the optimiser may use [m]."""
ATTACH_BOX = 0.005
"""Half-width of the cube around the exact spring attachment the optimiser may use [m]: the nearest
catalog rate is within a few per cent of the exact stiffness, i.e. ~1.5 mm of the 50 mm arm."""
FORCE_MARGIN = 1.25
"""A catalog spring is chosen only if rated for this multiple of the largest tension on the grid [1]."""


def optimise(
    robot: str, design: Fastened, grid: np.ndarray, tmp: Path, box: float = BOX
) -> tuple[Fastened, float]:
    """Re-balance ``design`` with its rods and posts counted: counterweight masses and centres (within
    ``box`` across the joint axis, ``BOX`` by default) and the spring stiffness, minimising the worst
    holding residual on ``grid``.

    Returns:
        The balanced design and its worst residual on the grid [N m].
    """
    path = write_leader(robot, design, tmp / f"{robot}_posts", with_counterweights=False)
    m = mujoco.MjModel.from_xml_path(str(path))
    km = model_from_mujoco(m)
    d = mujoco.MjData(m)
    mujoco.mj_kinematics(m, d)
    import pinocchio as pin

    q0 = np.array([m.qpos0[m.jnt_qposadr[j]] for j in km.mj_joint_ids])
    pin.forwardKinematics(km.model, km.data, q0)

    def to_joint(link: str, local: np.ndarray) -> tuple[int, np.ndarray]:
        b = m.body(link).id
        world = d.xpos[b] + d.xmat[b].reshape(3, 3) @ local
        jid = km.mj_joint_ids.index(int(m.body_jntadr[b])) + 1
        oMi = km.data.oMi[jid]
        return jid, oMi.rotation.T @ (world - oMi.translation)

    def to_link(link: str, jid: int, local: np.ndarray) -> np.ndarray:
        oMi = km.data.oMi[jid]
        world = oMi.translation + oMi.rotation @ local
        b = m.body(link).id
        return d.xmat[b].reshape(3, 3).T @ (world - d.xpos[b])

    lam = ROD_DENSITY * np.pi * ARM_RADIUS**2
    cw_slots = []
    for i, (link, centre, mass, start) in enumerate(design.counterweights):
        jid, c = to_joint(link, centre)
        _, s = to_joint(link, start)
        half = np.array([box, box, 0.0])  # axial height kept: it is what clears the neighbouring links
        cw_slots.append(
            CounterweightSlot(
                f"cw{i}", jid, tuple(c - half), tuple(c + half), 3.0 * mass + 0.05, tuple(s), lam
            )
        )
    sp_slots = []
    if design.spring is not None:
        l1, p1, _, l2, p2, _, k = design.spring
        j1, a = to_joint(l1, p1)
        j2, b = to_joint(l2, p2)
        rate = catalog_spring(m, grid, k).rate
        near = np.full(3, ATTACH_BOX)
        sp_slots.append(
            SpringSlot("spring", j1, tuple(a), tuple(a), j2, tuple(b - near), tuple(b + near), rate, rate)
        )
    res = optimise_balance(
        km, grid, counterweights=tuple(cw_slots), springs=tuple(sp_slots), mass_weight=1e-3
    )
    pin.forwardKinematics(km.model, km.data, q0)  # the optimiser left the last grid pose in km.data
    cws = []
    for slot, (link, _, _, start) in zip(cw_slots, design.counterweights, strict=True):
        c, mass, _ = res.counterweights[slot.name]
        cws.append((link, to_link(link, slot.joint, c), mass, start))
    spring = None
    if design.spring is not None:
        l1, p1, s1, l2, _, s2, _ = design.spring
        _, b, rate = res.springs["spring"]
        spring = (l1, p1, s1, l2, to_link(l2, sp_slots[0].attach_joint, b), s2, rate)
    return Fastened(tuple(cws), spring, design.posts, design.anchor_elbow), res.worst_residual


def catalog_spring(m: mujoco.MjModel, grid: np.ndarray, stiffness: float):
    """The catalog spring nearest in rate to ``stiffness`` [N/m] among those rated for ``FORCE_MARGIN``
    times the largest tension ``stiffness x L`` of ``m``'s (zero-length) spring tendon on ``grid``."""
    from rle_design.catalog import load_catalog

    d = mujoco.MjData(m)
    longest = 0.0
    for q in grid:
        d.qpos[:] = q
        mujoco.mj_fwdPosition(m, d)
        longest = max(longest, float(d.ten_length[0]))
    fits = [e for e in load_catalog("springs") if e.max_force >= FORCE_MARGIN * stiffness * longest]
    if not fits:
        raise ValueError(f"no catalog spring carries {FORCE_MARGIN * stiffness * longest:.1f} N")
    return min(fits, key=lambda e: abs(np.log(e.rate / stiffness)))
