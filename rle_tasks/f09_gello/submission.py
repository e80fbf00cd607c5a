"""Loading a submitted leader and every rule ``load_submission`` applies to it; the report's springs.

Structure rules (each violation is a ``Finding`` with a stable code; any of them is a structure
failure that skips the submitted-arm battery):

* MJCF contract (``rle_design.mjcf.contract``): no ``gravcomp``, no ``<option>`` change, no weld or
  connect to the world, no actuator, one root body, no body inside ``<frame>``;
* ``contract.equality``: no equality constraint at all; ``contract.extra_joint``: no new joint;
* ``contract.joint_frame``: every stock body keeps its parent, position and orientation, every stock
  joint its position, axis, range and reference angle ``ref`` (1e-6);
* ``contract.stock_servo``: stock joint frictionloss, damping and armature unchanged;
* ``contract.stock_body_addition``: no geom added to a stock body (its inertial is explicit, so the
  geom's mass would not count): parts go on new bodies welded to a link;
* tendons are springs only: ``contract.fixed_tendon`` (not a straight site-to-site spatial tendon),
  ``contract.tendon_friction``, ``contract.tendon_damping``, ``contract.tendon_armature``,
  ``contract.tendon_limit``; every spring (tendon or joint stiffness) is listed in the report;
* ``contract.stock_geometry`` / ``contract.stock_inertia``: stock geoms (type, size, placement) and
  stock body inertials (mass, centre of mass, inertia) unchanged: add mass as new welded bodies;
* build-ability (``buildable.py``): ``contract.floating_part``, ``contract.spring_anchor``,
  ``contract.spring_path``, springs as catalog parts (``contract.spring_catalog``,
  ``contract.spring_push``, ``contract.spring_overload``) and the workshop rules: catalog materials
  (``contract.underweight_part``, ``contract.point_mass``, ``contract.material_density``), inertials
  from the geometry (``contract.mass_mismatch`` ...), seats (``contract.interpenetration``) and
  strength (``contract.overstressed_part``, ``contract.flexible_part``).

Validity rules (deductions, the battery still runs): device mass (bodies plus catalog springs)
<= 2.30 kg (``contract.over_mass``, a deduction growing linearly to its full 0.10 at 3.00 kg; a
heavier device is a structure failure, ``contract.mass_bound``);
added mesh parts printable in PLA (``contract.printability``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import mujoco
import numpy as np
import trimesh

from rle_design.errors import MjcfError
from rle_design.mjcf.contract import Finding, check_contract
from rle_design.mjcf.loader import Design, load_design
from rle_design.mjcf.spring_parts import spring_mass, spring_parts
from rle_tasks.f09_gello.constants import HARD_MASS_KG, MAX_MASS_KG
from rle_tasks.f09_gello.device import OBJ, stock_model, stock_names
from rle_tasks.f09_gello.stock_contract import _structure, model_contract


@dataclass
class Submission:
    """One robot's submitted leader.

    Attributes:
        robot: Follower id.
        design: Loaded design (None when loading failed).
        model: Compiled model (None when loading or compiling failed).
        structure: Findings that make the design unusable (battery skipped).
        validity: Findings that deduct from the score.
        added_bodies: Ids of bodies that are not in the stock assembly.
        mass: Device mass [kg].
    """

    robot: str
    design: Design | None = None
    model: mujoco.MjModel | None = None
    structure: list[Finding] = field(default_factory=list)
    validity: list[Finding] = field(default_factory=list)
    added_bodies: list[int] = field(default_factory=list)
    mass: float = float("nan")

    @property
    def usable(self) -> bool:
        return self.model is not None and not self.structure


def springs_summary(m: mujoco.MjModel) -> list[dict]:
    """Every element of ``m`` that adds passive torque, as reported: tendon springs and joint springs,
    each with the catalog spring it is (None when it is none) and that spring's mass."""
    out = []
    for p in spring_parts(m):
        row: dict = {p.kind: p.name}
        if p.kind == "tendon":
            row["stiffness_N_per_m"] = p.stiffness
            row["springlength_m"] = [float(x) for x in m.tendon_lengthspring[p.index]]
        else:
            row["stiffness_Nm_per_rad"] = p.stiffness
            row["springref_rad"] = float(m.qpos_spring[m.jnt_qposadr[p.index]])
        row["catalog"] = p.entry.id if p.entry is not None else None
        row["mass_kg"] = p.entry.mass if p.entry is not None else None
        out.append(row)
    return out


def mesh_of(m: mujoco.MjModel, mesh_id: int) -> trimesh.Trimesh:
    """A compiled mesh as a trimesh (MuJoCo's recentred frame) [m]."""
    va, vn = int(m.mesh_vertadr[mesh_id]), int(m.mesh_vertnum[mesh_id])
    fa, fn = int(m.mesh_faceadr[mesh_id]), int(m.mesh_facenum[mesh_id])
    return trimesh.Trimesh(m.mesh_vert[va : va + vn].copy(), m.mesh_face[fa : fa + fn].copy(), process=False)


def over_mass_fraction(mass: float) -> float:
    """Fraction of the full over-mass deduction for a device of ``mass`` [kg]: 0 at the cap, 1 at
    ``HARD_MASS_KG``, linear in between [1]."""
    return float(np.clip((mass - MAX_MASS_KG) / (HARD_MASS_KG - MAX_MASS_KG), 0.0, 1.0))


def _validity(robot: str, m: mujoco.MjModel, added: list[int], path: str) -> tuple[list[Finding], float]:
    from rle_design.mjcf.printability import printability_report

    out: list[Finding] = []
    mass = float(m.body_mass[1:].sum()) + spring_mass(m)  # springs' bodies are not modelled
    if MAX_MASS_KG < mass <= HARD_MASS_KG:
        out.append(
            Finding(
                "contract.over_mass",
                f"device mass {mass:.3f} kg exceeds {MAX_MASS_KG:.2f} kg: deduction "
                f"{over_mass_fraction(mass):.2f} x 0.10 (full at {HARD_MASS_KG:.2f} kg)",
                path=path,
            )
        )
    for b in added:
        for g in (g for g in range(m.ngeom) if m.geom_bodyid[g] == b):
            if m.geom_type[g] != mujoco.mjtGeom.mjGEOM_MESH:
                continue
            rep = printability_report(mesh_of(m, int(m.geom_dataid[g])), material="pla", n_samples=400)
            if not rep.passed:
                gname = mujoco.mj_id2name(m, OBJ.mjOBJ_GEOM, g) or f"geom{g}"
                out.append(
                    Finding(
                        "contract.printability",
                        f"added part '{gname}' is not printable: " + "; ".join(rep.reasons),
                        element="geom",
                        path=path,
                    )
                )
    return out, mass


def load_submission(robot: str, directory: Path) -> Submission:
    """Load, compile and check ``directory/lead.xml``; never raises for participant faults."""
    sub = Submission(robot)
    rel = f"{robot}/lead.xml"
    try:
        sub.design = load_design(directory, entry="lead.xml")
        sub.structure += [
            Finding(f.code, f.message, f.element, f.line, f"{robot}/{f.path}" if f.path else rel)
            for f in check_contract(sub.design, model_contract(robot))
        ]
        m = sub.design.compile()
    except MjcfError as exc:
        sub.structure.append(
            Finding(exc.code, exc.message, getattr(exc, "element", None), getattr(exc, "line", None), rel)
        )
        return sub
    sub.model = m
    sub.structure += _structure(robot, m, rel)
    stock_bodies = set(stock_names(robot)[0])
    sub.added_bodies = [
        b for b in range(1, m.nbody) if mujoco.mj_id2name(m, OBJ.mjOBJ_BODY, b) not in stock_bodies
    ]
    sub.validity, sub.mass = _validity(robot, m, sub.added_bodies, rel)
    from rle_tasks.f09_gello.buildable import buildability_findings
    from rle_tasks.f09_gello.public.gello_helpers import PUBLIC_GRID_SIZE, workspace_grid

    # spring paths are checked on the stock joints' grid; a leader with other joints already fails
    stock = stock_model(robot)
    same_joints = m.njnt == stock.njnt and m.nq == stock.nq
    public_grid = workspace_grid(stock.jnt_range, PUBLIC_GRID_SIZE) if same_joints else np.zeros((0, m.nq))
    sub.structure += buildability_findings(sub.design.fresh_spec(), m, sub.added_bodies, public_grid, rel)
    if sub.mass > HARD_MASS_KG:
        sub.structure.append(
            Finding(
                "contract.mass_bound",
                f"device mass {sub.mass:.3f} kg exceeds the hard bound {HARD_MASS_KG:.2f} kg "
                f"(cap {MAX_MASS_KG:.2f} kg): not the card's device",
                path=rel,
            )
        )
    return sub


def deductions(sub: Submission) -> list[tuple[str, float]]:
    """``(code, fraction)`` of each validity finding for ``Rubric.deduction`` (over-mass grows with
    the excess; the others are full)."""
    return [
        (f.code, over_mass_fraction(sub.mass) if f.code == "contract.over_mass" else 1.0)
        for f in sub.validity
    ]
