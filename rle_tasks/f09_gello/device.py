"""Loading a submitted leader, checking it against the stock assembly, and hidden device copies.

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

import functools
from dataclasses import dataclass, field
from pathlib import Path

import mujoco
import numpy as np
import trimesh

from rle_design.catalog import load_catalog
from rle_design.errors import MjcfError
from rle_design.mjcf.contract import Finding, ModelContract, check_contract
from rle_design.mjcf.loader import Design, load_design
from rle_design.mjcf.spring_parts import spring_mass, spring_parts
from rle_design.scene import (
    MassScale,
    PointMass,
    Uniform,
    Variation,
    VariationSpace,
    element_id,
    has_element,
)
from rle_tasks.f09_gello.assembly import HANDLE_SITE
from rle_tasks.f09_gello.constants import HARD_MASS_KG, MAX_MASS_KG

ASSET_DIR = Path(__file__).resolve().parent / "assets"
STEEL_DENSITY = float(load_catalog("materials").get("steel").density)
"""Nominal steel [kg/m^3] (materials catalog), what the reference's counterweights are made of."""
TOL = 1e-6
OBJ = mujoco.mjtObj


@functools.cache
def stock_model(robot: str) -> mujoco.MjModel:
    """Compiled stock leader of ``robot`` (shipped assets)."""
    return mujoco.MjModel.from_xml_path(str(ASSET_DIR / robot / "lead.xml"))


def stock_names(robot: str) -> tuple[list[str], list[str], list[str]]:
    """Stock body, joint and geom names."""
    m = stock_model(robot)
    bodies = [mujoco.mj_id2name(m, OBJ.mjOBJ_BODY, b) for b in range(1, m.nbody)]
    joints = [mujoco.mj_id2name(m, OBJ.mjOBJ_JOINT, j) for j in range(m.njnt)]
    geoms = [mujoco.mj_id2name(m, OBJ.mjOBJ_GEOM, g) for g in range(m.ngeom)]
    return bodies, joints, geoms


def model_contract(robot: str) -> ModelContract:
    bodies, joints, _ = stock_names(robot)
    return ModelContract(
        required={"body": tuple(bodies), "joint": tuple(joints), "site": (HANDLE_SITE,)},
        forbid_gravcomp=True,
        forbid_option_changes=True,
        forbid_world_welds=True,
        forbid_actuators=True,
        forbid_multiple_roots=True,
        forbid_frames=True,
    )


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


def _close(a, b) -> bool:
    return bool(np.allclose(np.asarray(a, float), np.asarray(b, float), atol=TOL, rtol=TOL))


def _structure(robot: str, m: mujoco.MjModel, path: str) -> list[Finding]:
    s = stock_model(robot)
    out: list[Finding] = []

    def bad(code: str, msg: str, element: str) -> None:
        out.append(Finding(code, msg, element=element, path=path))

    if m.neq:
        bad("contract.equality", f"{m.neq} equality constraint(s): none are allowed in a leader", "equality")
    if m.njnt != s.njnt:
        extra = [mujoco.mj_id2name(m, OBJ.mjOBJ_JOINT, j) for j in range(m.njnt)]
        bad(
            "contract.extra_joint",
            f"leader has {m.njnt} joints {extra}; the stock leader has {s.njnt}",
            "joint",
        )
        return out
    for b in range(1, s.nbody):
        name = mujoco.mj_id2name(s, OBJ.mjOBJ_BODY, b)
        if not has_element(m, "body", name):
            continue  # reported by the required-names check
        mb = element_id(m, "body", name)
        parent = mujoco.mj_id2name(m, OBJ.mjOBJ_BODY, int(m.body_parentid[mb])) or "world"
        sparent = mujoco.mj_id2name(s, OBJ.mjOBJ_BODY, int(s.body_parentid[b])) or "world"
        if parent != sparent or not (
            _close(m.body_pos[mb], s.body_pos[b]) and _close(m.body_quat[mb], s.body_quat[b])
        ):
            bad(
                "contract.joint_frame",
                f"stock body '{name}' moved (parent '{parent}', pos {m.body_pos[mb]}, "
                f"quat {m.body_quat[mb]}); expected parent '{sparent}', pos {s.body_pos[b]}, quat {s.body_quat[b]}",
                "body",
            )
        if not (
            _close(m.body_mass[mb], s.body_mass[b])
            and _close(m.body_ipos[mb], s.body_ipos[b])
            and _close(m.body_inertia[mb], s.body_inertia[b])
        ):
            bad(
                "contract.stock_inertia",
                f"stock body '{name}' inertial changed (mass {m.body_mass[mb]:.6g} kg, "
                f"stock {s.body_mass[b]:.6g} kg); add mass as new welded child bodies",
                "body",
            )
    for j in range(s.njnt):
        name = mujoco.mj_id2name(s, OBJ.mjOBJ_JOINT, j)
        if not has_element(m, "joint", name):
            continue
        mj = element_id(m, "joint", name)
        if not (
            _close(m.jnt_pos[mj], s.jnt_pos[j])
            and _close(m.jnt_axis[mj], s.jnt_axis[j])
            and _close(m.jnt_range[mj], s.jnt_range[j])
            and _close(m.qpos0[m.jnt_qposadr[mj]], s.qpos0[s.jnt_qposadr[j]])
            and m.jnt_type[mj] == s.jnt_type[j]
        ):
            bad(
                "contract.joint_frame",
                f"stock joint '{name}' changed position, axis, type, range or reference angle",
                "joint",
            )
        if not (
            _close(m.dof_frictionloss[mj], s.dof_frictionloss[j])
            and _close(m.dof_damping[mj], s.dof_damping[j])
            and _close(m.dof_armature[mj], s.dof_armature[j])
        ):
            bad(
                "contract.stock_servo",
                f"stock joint '{name}' servo friction/damping/armature changed "
                f"(frictionloss {m.dof_frictionloss[mj]:.6g}, stock {s.dof_frictionloss[j]:.6g} N m)",
                "joint",
            )
    out += _tendon_findings(m, path)
    stock_geoms = {mujoco.mj_id2name(s, OBJ.mjOBJ_GEOM, g) for g in range(s.ngeom)}
    stock_bodies = {mujoco.mj_id2name(s, OBJ.mjOBJ_BODY, b) for b in range(1, s.nbody)}
    for g in range(m.ngeom):
        gname = mujoco.mj_id2name(m, OBJ.mjOBJ_GEOM, g)
        bname = mujoco.mj_id2name(m, OBJ.mjOBJ_BODY, int(m.geom_bodyid[g]))
        if bname in stock_bodies and gname not in stock_geoms:
            # a stock body's inertial is explicit: a geom added to it would carry no mass at all
            bad(
                "contract.stock_body_addition",
                f"geom '{gname or f'geom{g}'}' added to stock body '{bname}': add parts as new bodies "
                "welded to the link, where their mass and printability are counted",
                "geom",
            )
    for g in range(s.ngeom):
        name = mujoco.mj_id2name(s, OBJ.mjOBJ_GEOM, g)
        mg = element_id(m, "geom", name) if has_element(m, "geom", name) else -1
        same = mg >= 0 and (
            m.geom_type[mg] == s.geom_type[g]
            and mujoco.mj_id2name(m, OBJ.mjOBJ_BODY, int(m.geom_bodyid[mg]))
            == mujoco.mj_id2name(s, OBJ.mjOBJ_BODY, int(s.geom_bodyid[g]))
            and _close(m.geom_size[mg], s.geom_size[g])
            and _close(m.geom_pos[mg], s.geom_pos[g])
            and _close(m.geom_quat[mg], s.geom_quat[g])
            and _close(m.geom_rbound[mg], s.geom_rbound[g])
        )
        if not same:
            bad(
                "contract.stock_geometry",
                f"stock geom '{name}' removed or changed (link geometry, servo bodies "
                "and the base mount must be preserved)",
                "geom",
            )
    return out


def _tendon_findings(m: mujoco.MjModel, path: str) -> list[Finding]:
    """Tendons may only be springs: a straight site-to-site spatial tendon with ``stiffness`` and
    ``springlength``. Friction, damping, armature and limits would hold the arm without
    compensating it (or destabilise the simulation), and a fixed tendon is no part that can be built."""
    out = []
    for t in range(m.ntendon):
        name = mujoco.mj_id2name(m, OBJ.mjOBJ_TENDON, t) or f"tendon{t}"
        adr, num = int(m.tendon_adr[t]), int(m.tendon_num[t])
        kinds = {int(k) for k in m.wrap_type[adr : adr + num]}
        checks = (
            ("contract.fixed_tendon", kinds != {int(mujoco.mjtWrap.mjWRAP_SITE)}, "is not a straight site-to-site spatial tendon (springs only)"),
            ("contract.tendon_friction", m.tendon_frictionloss[t] > 0, f"has frictionloss {m.tendon_frictionloss[t]:.6g} N"),
            ("contract.tendon_damping", m.tendon_damping[t] > 0, f"has damping {m.tendon_damping[t]:.6g} N s/m"),
            ("contract.tendon_armature", m.tendon_armature[t] > 0, f"has armature {m.tendon_armature[t]:.6g} kg"),
            ("contract.tendon_limit", bool(m.tendon_limited[t]), "is limited (a tendon stop)"),
        )  # fmt: skip
        for code, bad, what in checks:
            if bad:
                out.append(
                    Finding(
                        code,
                        f"tendon '{name}' {what}: only springs (stiffness, springlength) are allowed",
                        element="tendon",
                        path=path,
                    )
                )
    return out


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


def battery_model(m: mujoco.MjModel) -> mujoco.MjModel:
    """Copy with the verifier's physics: dt 2 ms, noslip 10 (frictionloss sticks), no contacts."""
    b = mujoco.MjModel.from_xml_string("<mujoco/>") if m is None else _copy(m)
    b.opt.timestep = 0.002
    b.opt.noslip_iterations = 10
    b.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONTACT)
    return b


def _copy(m: mujoco.MjModel) -> mujoco.MjModel:
    import copy

    return copy.deepcopy(m)


def device_variations(
    dof: int, spread: float = 0.15, payload: tuple[float, float] = (0.01, 0.04)
) -> VariationSpace:
    """Hidden device copies: stock link masses (and inertias) uniformly within +-``spread``, and a point
    payload uniform in ``payload`` [kg] merged into the handle's body at the handle site."""
    links = tuple(f"link{k + 1}" for k in range(dof))
    return VariationSpace(
        (
            MassScale("link_scale", Uniform(1 - spread, 1 + spread, "1"), bodies=links),
            PointMass("payload", Uniform(*payload, "kg"), site=HANDLE_SITE),
        )
    )


def draw_variation(rng: np.random.Generator, dof: int) -> Variation:
    """One hidden device copy of a leader with ``dof`` joints."""
    return device_variations(dof).sample(rng)


def apply_variation(m: mujoco.MjModel, var: Variation) -> mujoco.MjModel:
    """Copy of ``m`` with the variation applied."""
    return var.apply(m)
