"""Validity of a submitted base: contract names, catalog profiles, immutable parts, mount, clearance."""

from __future__ import annotations

import mujoco
import numpy as np

from rle_design.catalog import load_catalog, part_fragment_path
from rle_design.mjcf import Design, ModelContract, check_contract, match_profiles
from rle_design.mjcf.buildability import audit_buildability
from rle_design.scene import element_id
from rle_tasks.f08_mobile_base.public.scene import ADAPTER, BATTERY, CHASSIS, MOUNT_SITE
from rle_tasks.f08_mobile_base.public.wheels import WHEELS
from rle_tasks.f08_mobile_base.public.workshop import workshop_findings_of

CONTRACT = ModelContract(
    required={"body": (CHASSIS, *WHEELS, BATTERY, ADAPTER), "site": (MOUNT_SITE,)},
    forbid_gravcomp=True,
    forbid_option_changes=True,
    forbid_world_welds=True,
    forbid_actuators=True,
    forbid_multiple_roots=True,
)
PART_OF = {BATTERY: "battery", ADAPTER: "universal_adapter", **{w: "mecanum_wheel" for w in WHEELS}}
MASS_RTOL = 1e-3
MOUNT_TOL = 0.002  # [m]
COM_TOL = 0.001  # a catalog part's centre of mass against its fragment's [m]
JOIN_TOL = 0.001  # surfaces within 1 mm are joined (bolted, welded, resting) [m]
WHEEL_HUB_GAP = 0.006  # a wheel's hub motor spans up to 6 mm between its inner face and the frame [m]


def _fragment(part_id: str) -> tuple[float, np.ndarray, np.ndarray, list[tuple[int, np.ndarray]]]:
    part = load_catalog("parts").get(part_id)
    m = mujoco.MjModel.from_xml_path(str(part_fragment_path(part)))
    return (
        float(m.body_mass[1]),
        m.body_inertia[1].copy(),
        m.body_ipos[1].copy(),
        [(int(m.geom_type[g]), m.geom_size[g].copy()) for g in range(m.ngeom)],
    )


def _massive_extras(design: Design) -> list[tuple[str, str]]:
    """Geoms of the chassis that are neither profiles nor massless: "other geoms carry no mass" (a
    geom carries mass unless its ``mass`` is 0, or its ``density`` is 0 with no ``mass`` given)."""
    out = []
    for g in design.fresh_spec().body(CHASSIS).geoms:
        if g.name.startswith("profile_"):
            continue
        if g.mass > 0 or (np.isnan(g.mass) and g.density > 0):
            what = f"mass {g.mass:g} kg" if g.mass > 0 else f"density {g.density:g} kg/m^3"
            out.append(
                (
                    "catalog.non_catalog_mass",
                    f"geom '{g.name or 'unnamed'}' of '{CHASSIS}' is no catalog profile but carries mass "
                    f'({what}); other geoms must have mass="0"',
                )
            )
    return out


def check_validity(design: Design) -> list[tuple[str, str]]:
    """(code, message) of every violation; an empty list means valid. Compiles the design."""
    out = [(f.code, f.message) for f in check_contract(design, CONTRACT)]
    if out:
        return out
    model = design.compile()
    chassis = element_id(model, "body", CHASSIS)
    if (
        model.body_parentid[chassis] != 0
        or model.body_jntnum[chassis] != 1
        or model.jnt_type[model.body_jntadr[chassis]] != mujoco.mjtJoint.mjJNT_FREE
    ):
        out.append(
            ("f08.chassis_not_free", f"body '{CHASSIS}' must be the root body with exactly one <freejoint/>")
        )
    others = [model.joint(j).name or f"joint{j}" for j in range(model.njnt) if model.jnt_bodyid[j] != chassis]
    if others:
        out.append(
            (
                "f08.extra_joints",
                f"joints other than the chassis freejoint are not allowed: {', '.join(others)}",
            )
        )
    allowed = {CHASSIS, *PART_OF}
    extra = [
        model.body(b).name or f"body{b}" for b in range(1, model.nbody) if model.body(b).name not in allowed
    ]
    if extra:
        out.append(
            (
                "f08.extra_body",
                f"bodies other than '{CHASSIS}' and the catalog parts are not part of the contract: "
                f"{', '.join(extra)} (profiles are geoms of '{CHASSIS}')",
            )
        )
    out += _massive_extras(design)
    for p in match_profiles(design, model).findings:
        out.append((p.code, p.message))
    for body, pid in PART_OF.items():
        b = element_id(model, "body", body)
        mass, inertia, com, geoms = _fragment(pid)
        if (
            abs(model.body_mass[b] - mass) > MASS_RTOL * mass
            or np.any(np.abs(np.sort(model.body_inertia[b]) - np.sort(inertia)) > 0.01 * inertia.max())
            or np.linalg.norm(model.body_ipos[b] - com) > COM_TOL
        ):
            out.append(
                (
                    "f08.part_modified",
                    f"body '{body}' must carry the catalog part '{pid}' unchanged: mass {model.body_mass[b]:.4f} kg "
                    f"vs {mass:.4f} kg, centre of mass {np.round(model.body_ipos[b], 4).tolist()} vs "
                    f"{np.round(com, 4).tolist()} m",
                )
            )
        mine = sorted(
            (int(model.geom_type[g]), tuple(np.round(model.geom_size[g], 4)))
            for g in range(model.ngeom)
            if model.geom_bodyid[g] == b
        )
        want = sorted((t, tuple(np.round(s, 4))) for t, s in geoms)
        if mine != want:
            out.append(
                (
                    "f08.part_modified",
                    f"body '{body}' geoms {mine} differ from catalog part '{pid}' geoms {want}",
                )
            )
    # the workshop rules (public/workshop.py): no part inside another (every part is welded to the
    # chassis, so MuJoCo never collides them), the chassis' inertial from its geoms
    out += [(f.code, f.message) for f in workshop_findings_of(design.fresh_spec(), model)]
    hubs = {w: WHEEL_HUB_GAP for w in WHEELS}
    out += [
        ("f08.floating_part", d.message) for d in audit_buildability(model, tol=JOIN_TOL, parent_tol=hubs)
    ]
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    rc = data.xmat[chassis].reshape(3, 3)
    for w in WHEELS:
        rw = data.xmat[element_id(model, "body", w)].reshape(3, 3)
        if np.linalg.norm(rw - rc) > 1e-3:
            out.append(
                ("f08.wheel_orientation", f"body '{w}' must be aligned with '{CHASSIS}' (axle along y)")
            )
    site = element_id(model, "site", MOUNT_SITE)
    adapter = element_id(model, "body", ADAPTER)
    if model.site_bodyid[site] != adapter:
        out.append(("f08.mount_not_on_adapter", f"site '{MOUNT_SITE}' must belong to body '{ADAPTER}'"))
    elif (
        np.linalg.norm(model.site_pos[site] - [0, 0, 0.015]) > MOUNT_TOL
        or abs(data.site_xmat[site][8] - 1.0) > 1e-4
    ):
        out.append(
            (
                "f08.mount_misplaced",
                f"site '{MOUNT_SITE}' must be at the adapter top centre (0 0 0.015) with z up",
            )
        )
    loose = [
        model.geom(g).name or f"geom{g}"
        for g in range(model.ngeom)
        if model.geom_bodyid[g] == chassis
        and not (model.geom(g).name or "").startswith("profile_")
        and (model.geom_contype[g] or model.geom_conaffinity[g])
    ]
    if loose:
        out.append(
            (
                "catalog.non_catalog_geom",
                f"colliding geoms must be catalog profiles or parts: {', '.join(loose)}",
            )
        )
    expected = sum(p.expected_mass for p in match_profiles(design, model).profiles) + 4 * 1.0 + 3.5 + 1.62
    total = float(model.body_subtreemass[chassis])
    if abs(total - expected) > 0.02 * expected:
        out.append(
            (
                "catalog.unaccounted_mass",
                f"base mass {total:.3f} kg != catalog profiles and parts {expected:.3f} kg",
            )
        )
    return out


def interpenetration(
    model: mujoco.MjModel, data: mujoco.MjData, robot: np.ndarray, tol: float = 0.001
) -> list[str]:
    """Robot geoms that penetrate each other, or touch the floor other than through the wheels."""
    rob = set(int(g) for g in robot)
    floor = element_id(model, "geom", "floor")
    bad = []
    for c in data.contact[: data.ncon]:
        g1, g2 = int(c.geom1), int(c.geom2)
        n1, n2 = model.geom(g1).name, model.geom(g2).name
        if n1.endswith("_contact") or n2.endswith("_contact"):
            continue
        if (g1 in rob and g2 in rob and c.dist < -tol) or ({g1, g2} & rob and floor in (g1, g2)):
            bad.append(f"{n1 or g1} / {n2 or g2} ({c.dist * 1e3:.1f} mm)")
    return bad


__all__ = ["CONTRACT", "check_validity", "interpenetration"]
