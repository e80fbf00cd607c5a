"""A submitted leader checked against the stock assembly of its robot (structure rules).

``model_contract`` requires the stock bodies, joints and handle site and forbids gravcomp, option
changes, world welds, actuators, several roots and frames (``rle_design.mjcf.contract``);
``_structure`` compares the compiled leader with the stock one (no equality, no new joint, stock
frames, joints, servo parameters, geometry and inertials unchanged within ``TOL``, no geom added to a
stock body), and ``_tendon_findings`` allows tendons only as straight site-to-site springs.
"""

from __future__ import annotations

import mujoco
import numpy as np

from rle_design.mjcf.contract import Finding, ModelContract
from rle_design.scene import element_id, has_element
from rle_tasks.f09_gello.assembly import HANDLE_SITE
from rle_tasks.f09_gello.device import OBJ, stock_model, stock_names

TOL = 1e-6


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
