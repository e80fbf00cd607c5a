"""Builds the shipped solutions: ``python -m rle_tasks.f09_gello.solutions``.

Reference (``reference/<robot>/``), derivation:

1. Candidate passive elements, each linear in one unknown: steel counterweights behind joints 2..n
   (point mass at ``CW_RADIUS`` opposite the link, ``CW_AXIAL`` to either side along the joint axis so
   it sweeps free space; the torque is linear in the mass),
   an ideal zero-length spring across the shoulder (anchor ``SPRING_ARM`` straight above joint 2 on
   link 1, attachment ``SPRING_ARM`` along the upper arm; torque linear in the stiffness; exact for a
   rigid upper arm since k a b = m g l), and torsion springs on joints 2..n (stiffness and
   stiffness x rest angle).
2. The residual r(q) = g(q) + sum m_c G_c(q) - k T(q) - ... over a public workspace grid is linear in
   those unknowns: bounded least squares (masses and stiffnesses >= 0) with a mass penalty raised
   until the device stays under ``MASS_TARGET``.
3. ``trim.py`` (shared by the three robots) fits the identifiable gravity parameters (QR base
   parameters of the Pinocchio regressor) to the 16 probes with a small ridge to the nominal values,
   after a greedy D-optimal probe plan over a candidate grid.

Baselines (``baseline/<name>/<robot>/``): ``uncompensated`` (stock leader, zero feedforward),
``gravcomp_cheat`` (stock leader with ``gravcomp="1"`` on every link), ``over_mass`` (reference plus a
2 kg steel block on the base) and ``hanging_trim`` (reference leader, ``adapt`` never returns).
"""

from __future__ import annotations

import shutil
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin
import scipy.optimize
from lxml import etree

from rle_design.kinematics import GravityMap, TendonSpring, model_from_mujoco, spring_torque
from rle_tasks.f09_gello.device import ASSET_DIR, STEEL_DENSITY
from rle_tasks.f09_gello.helpers import workspace_grid
from rle_tasks.f09_gello.leaders import ROBOTS

PKG = Path(__file__).resolve().parent
CW_RADIUS = 0.06
CW_AXIAL = 0.055
SPRING_ARM = 0.05
SPRING_OFFSET = 0.03
MASS_TARGET = 2.0
TRIM_TEMPLATES = PKG / "trim_templates"


@dataclass(frozen=True)
class Design:
    """Solved passive elements of one leader (body-frame positions [m], masses [kg], stiffnesses)."""

    counterweights: tuple[tuple[str, tuple[float, float, float], float], ...]
    spring: tuple[str, tuple[float, ...], str, tuple[float, ...], float] | None
    torsion: tuple[tuple[str, float, float], ...]


def _point_mass_columns(km, jid: int, local: np.ndarray, grid: np.ndarray) -> np.ndarray:
    """Holding torque of a 1 kg point at ``local`` in joint ``jid``'s frame, over the grid."""
    model, data = km.model, km.data
    gvec = np.asarray(model.gravity.linear)
    out = np.empty_like(grid)
    for k, q in enumerate(grid):
        pin.computeJointJacobians(model, data, q)
        oMi = data.oMi[jid]
        p = oMi.translation + oMi.rotation @ local
        j6 = np.reshape(pin.getJointJacobian(model, data, jid, pin.LOCAL_WORLD_ALIGNED), (6, model.nv))
        jl = j6[:3] - np.cross(p - oMi.translation, j6[3:].T).T
        out[k] = -jl.T @ gvec
    return out


def solve_design(robot: str, n_grid: int = 600, seed: int = 7, verbose: bool = False) -> Design:
    """Counterweights, shoulder spring and torsion springs minimising the grid residual."""
    m = mujoco.MjModel.from_xml_path(str(ASSET_DIR / robot / "lead.xml"))
    km = model_from_mujoco(m)
    n = m.nv
    grid = workspace_grid(m.jnt_range, n_grid, seed=seed)
    g0 = GravityMap(km)(grid)
    cols, kinds = [], []
    d = mujoco.MjData(m)
    mujoco.mj_kinematics(m, d)
    for j in range(2, n + 1):  # counterweights behind joints 2..n, opposite the link's own COM / child
        body = m.body(f"link{j}").id
        ref = m.body_ipos[body].copy() if j == n else m.body_pos[body + 1].copy()
        ref[2] = 0.0
        if np.linalg.norm(ref) < 1e-4:
            continue
        for side in (1.0, -1.0):  # beside the links (axial offset) so the weight sweeps free space
            local = -CW_RADIUS * ref / np.linalg.norm(ref) + np.array([0.0, 0.0, side * CW_AXIAL])
            cols.append(_point_mass_columns(km, j, local, grid))
            kinds.append(("cw", f"link{j}", local))
    # shoulder zero-length spring: link1 anchor above joint 2, link2 attachment along the upper arm
    b1, b2 = m.body("link1").id, m.body("link2").id
    r12 = np.zeros(9)
    mujoco.mju_quat2Mat(r12, m.body_quat[b2])
    r12 = r12.reshape(3, 3)
    axis1 = r12[:, 2]
    up = np.array([0.0, 0.0, 1.0]) - axis1 * axis1[2]
    up /= np.linalg.norm(up)
    anchor = m.body_pos[b2] + SPRING_ARM * up + SPRING_OFFSET * axis1
    along = m.body_pos[b2 + 1].copy()
    along[2] = 0.0
    attach = SPRING_ARM * along / np.linalg.norm(along) + np.array([0.0, 0.0, SPRING_OFFSET])
    unit = TendonSpring("s", 1.0, (0.0, 0.0), points=((1, tuple(anchor)), (2, tuple(attach))))
    cols.append(-np.array([spring_torque(km, [unit], q) for q in grid]))
    kinds.append(("spring", anchor, attach))
    for j in range(2, n + 1):  # torsion springs: r += k q_j - (k ref)_j
        c = np.zeros_like(grid)
        c[:, j - 1] = grid[:, j - 1]
        cols.append(c)
        kinds.append(("k", j))
        c = np.zeros_like(grid)
        c[:, j - 1] = -1.0
        cols.append(c)
        kinds.append(("kref", j))
    a = np.stack([c.ravel() for c in cols], axis=1)
    lb = np.array([-np.inf if k[0] == "kref" else 0.0 for k in kinds])
    base_mass = float(m.body_mass.sum())
    is_cw = np.array([k[0] == "cw" for k in kinds])
    x = None
    for lam in (0.0, *np.geomspace(1e-3, 1e4, 22)):
        pen = np.sqrt(lam) * np.diag(is_cw.astype(float))[is_cw]
        aa = np.vstack([a, pen])
        bb = np.concatenate([-g0.ravel(), np.zeros(pen.shape[0])])
        x = scipy.optimize.lsq_linear(aa, bb, bounds=(lb, np.inf), method="bvls").x
        if base_mass + x[is_cw].sum() <= MASS_TARGET:
            break
        if verbose:
            res = (a @ x + g0.ravel()).reshape(g0.shape)
            print(
                f"  lambda {lam:.3g}: mass {base_mass + x[is_cw].sum():.3f} kg, "
                f"p95 {np.percentile(np.abs(res).max(1), 95):.4f} N m"
            )
    if verbose:
        res = (a @ x + g0.ravel()).reshape(g0.shape)
        print(
            f"  final: mass {base_mass + x[is_cw].sum():.3f} kg, p95 {np.percentile(np.abs(res).max(1), 95):.4f}, "
            f"max {np.abs(res).max(0).round(3)} N m"
        )
    cws, torsion, spring, kk = [], [], None, {}
    for val, kind in zip(x, kinds):
        if kind[0] == "cw" and val > 1e-3:
            cws.append((kind[1], tuple(float(v) for v in kind[2]), float(val)))
        elif kind[0] == "spring" and val > 1e-6:
            spring = (
                "link1",
                tuple(float(v) for v in kind[1]),
                "link2",
                tuple(float(v) for v in kind[2]),
                float(val),
            )
        elif kind[0] in ("k", "kref"):
            kk.setdefault(kind[1], {})[kind[0]] = float(val)
    for j, v in sorted(kk.items()):
        if v.get("k", 0.0) > 1e-6:
            torsion.append((f"j{j}", v["k"], v["kref"] / v["k"]))
    _ = b1
    return Design(tuple(cws), spring, tuple(torsion))


def _fmt(v) -> str:
    return " ".join(f"{float(x):.9g}" for x in np.ravel(v))


def apply_design(robot: str, design: Design, out_dir: Path) -> Path:
    """Write the stock leader with the design's elements added into ``out_dir``."""
    src = ASSET_DIR / robot
    if out_dir.exists():
        shutil.rmtree(out_dir)
    shutil.copytree(src, out_dir)
    tree = etree.parse(str(out_dir / "lead.xml"))
    root = tree.getroot()

    def body(name: str):
        return next(b for b in root.iter("body") if b.get("name") == name)

    for k, (link, pos, mass) in enumerate(design.counterweights):
        radius = (3 * mass / (4 * np.pi * STEEL_DENSITY)) ** (1 / 3)
        cw = etree.SubElement(body(link), "body", name=f"counterweight{k + 1}", pos=_fmt(pos))
        etree.SubElement(
            cw,
            "geom",
            name=f"counterweight{k + 1}_steel",
            type="sphere",
            size=f"{radius:.9g}",
            mass=f"{mass:.9g}",
            rgba="0.5 0.5 0.55 1",
        )
    if design.spring is not None:
        l1, p1, l2, p2, k = design.spring
        etree.SubElement(body(l1), "site", name="spring_anchor", pos=_fmt(p1), size="0.004")
        etree.SubElement(body(l2), "site", name="spring_attach", pos=_fmt(p2), size="0.004")
        tendon = etree.SubElement(root, "tendon")
        sp = etree.SubElement(
            tendon,
            "spatial",
            name="shoulder_spring",
            stiffness=f"{k:.9g}",
            springlength="0",
            width="0.002",
            rgba="0.2 0.6 0.9 1",
        )
        etree.SubElement(sp, "site", site="spring_anchor")
        etree.SubElement(sp, "site", site="spring_attach")
    for jname, k, ref in design.torsion:
        j = next(e for e in root.iter("joint") if e.get("name") == jname)
        j.set("stiffness", f"{k:.9g}")
        j.set("springref", f"{ref:.9g}")
    etree.indent(tree, space="  ")
    path = out_dir / "lead.xml"
    tree.write(str(path), xml_declaration=False, encoding="utf-8")
    return path


def build_all(target: Path = PKG) -> None:
    """Reference and baselines for every robot."""
    for robot in ROBOTS:
        des = solve_design(robot, verbose=True)
        ref = target / "reference" / robot
        apply_design(robot, des, ref)
        shutil.copy(TRIM_TEMPLATES / "regressor_trim.py", ref / "trim.py")
        m = mujoco.MjModel.from_xml_path(str(ref / "lead.xml"))
        print(f"{robot}: reference mass {m.body_mass.sum():.3f} kg, {des}")

        base = target / "baseline"
        unc = base / "uncompensated" / robot
        apply_design(robot, Design((), None, ()), unc)
        shutil.copy(TRIM_TEMPLATES / "zero_trim.py", unc / "trim.py")

        cheat = base / "gravcomp_cheat" / robot
        apply_design(robot, Design((), None, ()), cheat)
        text = (cheat / "lead.xml").read_text()
        (cheat / "lead.xml").write_text(text.replace('<body name="link', '<body gravcomp="1" name="link'))
        shutil.copy(TRIM_TEMPLATES / "zero_trim.py", cheat / "trim.py")

        heavy = base / "over_mass" / robot
        apply_design(robot, des, heavy)
        tree = etree.parse(str(heavy / "lead.xml"))
        base_body = next(b for b in tree.getroot().iter("body") if b.get("name") == "base")
        ballast = etree.SubElement(base_body, "body", name="ballast", pos="0.1 0 0.01")
        etree.SubElement(
            ballast,
            "geom",
            name="ballast_steel",
            type="box",
            size="0.04 0.04 0.02",
            mass="2.0",
            rgba="0.4 0.4 0.4 1",
        )
        etree.indent(tree, space="  ")
        tree.write(str(heavy / "lead.xml"), encoding="utf-8")
        shutil.copy(TRIM_TEMPLATES / "regressor_trim.py", heavy / "trim.py")

        hang = base / "hanging_trim" / robot
        apply_design(robot, des, hang)
        shutil.copy(TRIM_TEMPLATES / "hanging_trim.py", hang / "trim.py")


if __name__ == "__main__":
    build_all()
