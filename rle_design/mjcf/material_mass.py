"""Mass where the material is: a body's ``<inertial>`` against its geometry times catalog materials.

For every audited body (one a submission adds or changes):

1. each solid geom's density, its declared ``mass`` over its closed-form volume (or its ``density``),
   lies within the ``[density_min, density_max]`` range of some material of
   ``catalogs/materials.yaml`` (exact edges, ``DENSITY_RTOL`` for 9-digit XML rounding): lighter than
   every material is ``material.too_light``, denser than every one ``material.too_dense``, between
   two ranges ``material.density``; a geom declared massless (``mass="0"``, or ``density="0"``) is no part and is skipped
   unless ``massless_ok`` is False;
2. the body's inertial (explicit or not) equals what MuJoCo derives from those geoms as solids
   (``inertiafromgeom="true"``, every geom group, no shell inertia): mass within ``mass_rtol`` (``inertial.mass_mismatch``), centre of mass
   within ``com_tol`` (``inertial.com_mismatch``), inertia tensor in the body frame within
   ``inertia_rtol`` of the largest computed principal moment (``inertial.inertia_mismatch``);
3. the declared centre of mass lies inside the convex hull of the body's geoms (``com_tol`` slack,
   ``inertial.com_outside``).

SI units: kg, m, kg m^2, kg/m^3.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import mujoco
import numpy as np

from rle_design.catalog import Material, load_catalog
from rle_design.mjcf.contract import Finding
from rle_design.mjcf.geom_solid import geom_trimesh, geom_volume, is_solid

__all__ = ["DENSITY_RTOL", "InertialTolerance", "geom_masses", "material_for", "material_findings"]

DENSITY_RTOL = 1e-6
"""Relative slack on a material's density edges [1]: mass and size written to 9 digits give the
density to ~1e-8; 1e-6 is that rounding, not a tolerance (1 % over steel is refused)."""


@dataclass(frozen=True)
class InertialTolerance:
    """How closely a declared inertial must match its geometry.

    Attributes:
        mass_rtol: Relative mass tolerance [1].
        com_tol: Centre-of-mass distance tolerance, also the slack of the hull test [m].
        inertia_rtol: Largest tensor entry difference, relative to the largest principal moment [1].
    """

    mass_rtol: float = 1e-3
    com_tol: float = 1e-3
    inertia_rtol: float = 0.01


def _name(model: mujoco.MjModel, kind: mujoco.mjtObj, i: int) -> str:
    return mujoco.mj_id2name(model, kind, i) or f"{kind.name[6:].lower()}{i}"


def geom_masses(spec: mujoco.MjSpec, model: mujoco.MjModel) -> np.ndarray:
    """Each compiled geom's mass from its declaration: ``mass`` when given, else ``density`` x its
    closed-form volume [kg] (planes and height fields: 0).

    Raises:
        ValueError: The spec's geoms do not correspond to the model's (a bug: spec and model differ).
    """
    geoms = spec.worldbody.find_all(mujoco.mjtObj.mjOBJ_GEOM)
    if len(geoms) != model.ngeom:
        raise ValueError(f"spec has {len(geoms)} geoms, model {model.ngeom}")
    out = np.zeros(model.ngeom)
    for g, sg in enumerate(geoms):
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, g) or ""
        if sg.name != name:
            raise ValueError(f"spec geom {g} is '{sg.name}', model geom {g} is '{name}'")
        if not is_solid(model, g):
            continue
        out[g] = float(sg.mass) if np.isfinite(sg.mass) else float(sg.density) * geom_volume(model, g)
    return out


def material_for(density: float, materials: Iterable[Material]) -> Material | None:
    """The first catalog material whose density range holds ``density`` [kg/m^3], or None."""
    for mat in materials:
        lo, hi = mat.density_range
        if lo * (1 - DENSITY_RTOL) <= density <= hi * (1 + DENSITY_RTOL):
            return mat
    return None


def _density_findings(
    model, b: int, masses: np.ndarray, materials: list[Material], massless_ok: bool
) -> list[Finding]:
    out = []
    ranges = ", ".join(f"{m.id} {m.density_range[0]:g}-{m.density_range[1]:g}" for m in materials)
    for g in np.flatnonzero(model.geom_bodyid == b):
        if not is_solid(model, int(g)):
            continue
        vol = geom_volume(model, int(g))
        if masses[g] == 0.0 and massless_ok:
            continue
        rho = masses[g] / vol if vol > 0 else np.inf
        if material_for(rho, materials) is None:
            lightest = min(m.density_range[0] for m in materials)
            densest = max(m.density_range[1] for m in materials)
            code = (
                "material.too_light"
                if rho < lightest
                else "material.too_dense"
                if rho > densest
                else "material.density"
            )
            out.append(
                Finding(
                    code,
                    f"part '{_name(model, mujoco.mjtObj.mjOBJ_GEOM, int(g))}' of body "
                    f"'{_name(model, mujoco.mjtObj.mjOBJ_BODY, b)}' has {masses[g]:.6g} kg in "
                    f"{vol * 1e6:.4g} cm^3 ({rho:.6g} kg/m^3): no catalog material has that density "
                    f"(kg/m^3: {ranges})",
                    element="geom",
                )
            )
    return out


def _from_geoms(spec: mujoco.MjSpec, model: mujoco.MjModel, b: int) -> bool:
    """Whether MuJoCo derived body ``b``'s inertial from its geoms (no explicit ``<inertial>``, and
    the compiler does not ignore the geoms)."""
    if spec.compiler.inertiafromgeom == mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_FALSE:
        return False
    if list(spec.compiler.inertiagrouprange) != [0, 5]:
        return False  # some geoms may not count towards the mass MuJoCo derives
    name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, b)
    body = spec.body(name) if name else None
    if body is None or body.explicitinertial:
        return False
    return all(
        g.typeinertia == mujoco.mjtGeomInertia.mjINERTIA_VOLUME and 0 <= g.group <= 5 for g in body.geoms
    )


def _tensor(model: mujoco.MjModel, b: int) -> np.ndarray:
    rot = np.zeros(9)
    mujoco.mju_quat2Mat(rot, model.body_iquat[b])
    rot = rot.reshape(3, 3)
    return rot @ np.diag(model.body_inertia[b]) @ rot.T


def _hull_margin(model: mujoco.MjModel, b: int, point: np.ndarray) -> float:
    """Signed distance of ``point`` (body frame) outside the convex hull of body ``b``'s geoms [m]."""
    import trimesh

    verts = []
    for g in np.flatnonzero(model.geom_bodyid == b):
        if not is_solid(model, int(g)):
            continue
        rot = np.zeros(9)
        mujoco.mju_quat2Mat(rot, model.geom_quat[g])
        verts.append(geom_trimesh(model, int(g)).vertices @ rot.reshape(3, 3).T + model.geom_pos[g])
    if not verts:
        return np.inf
    pts = np.vstack(verts)
    try:
        hull = trimesh.convex.convex_hull(pts)
    except Exception:  # noqa: BLE001 - a flat or degenerate body (qhull): fall back to its box
        return float(np.max(np.maximum(pts.min(0) - point, point - pts.max(0))))
    return float(
        np.max(hull.face_normals @ point - np.einsum("ij,ij->i", hull.face_normals, hull.triangles[:, 0]))
    )


def material_findings(
    spec: mujoco.MjSpec,
    model: mujoco.MjModel,
    bodies: Iterable[int],
    *,
    materials: Iterable[Material] | None = (),
    tol: InertialTolerance = InertialTolerance(),
    massless_ok: bool = True,
) -> list[Finding]:
    """Findings of the three rules above for the audited bodies.

    Args:
        spec: The design's spec (not modified; a copy is compiled).
        model: Its compiled model (the declared inertials).
        bodies: Ids of the audited bodies.
        materials: Catalog materials a part may be made of; ``()`` (default) means every entry of
            ``catalogs/materials.yaml``; None skips the density rule (parts whose mass is checked
            by another catalog, e.g. aluminium profiles by their kg/m).
        tol: Inertial tolerances.
        massless_ok: Whether a geom declared massless is allowed (a visual or clearance geom).

    Returns:
        ``material.too_light``, ``material.too_dense``, ``material.density``, ``inertial.mass_mismatch``, ``inertial.com_mismatch``,
        ``inertial.inertia_mismatch``, ``inertial.com_outside`` findings, each naming the body (and
        the part) with the declared and the computed numbers.
    """
    if materials is not None:
        materials = list(materials) or list(load_catalog("materials"))
    bodies = [int(b) for b in bodies]
    masses = geom_masses(spec, model) if materials is not None else None
    out: list[Finding] = []
    if materials is not None:
        for b in bodies:
            out += _density_findings(model, b, masses, materials, massless_ok)
    # a body whose inertial MuJoCo derived from its geoms agrees with them by construction
    declared = [b for b in bodies if not _from_geoms(spec, model, b)]
    if not declared:
        return out
    copy = spec.copy()
    copy.compiler.inertiafromgeom = mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_TRUE
    copy.compiler.inertiagrouprange = [0, 5]  # every part counts, as a solid
    for g in copy.geoms:
        g.typeinertia = mujoco.mjtGeomInertia.mjINERTIA_VOLUME
    try:
        geo = copy.compile()
    except ValueError as exc:
        return out + [
            Finding("inertial.mass_mismatch", f"the inertials cannot be derived from the geoms: {exc}")
        ]
    for b in declared:
        name = _name(model, mujoco.mjtObj.mjOBJ_BODY, b)
        m0, m1 = float(model.body_mass[b]), float(geo.body_mass[b])
        c0, c1 = model.body_ipos[b].copy(), geo.body_ipos[b].copy()
        i0, i1 = _tensor(model, b), _tensor(geo, b)
        scale = max(float(np.max(geo.body_inertia[b])), 1e-12)
        if abs(m0 - m1) > tol.mass_rtol * max(m1, 1e-9):
            out.append(
                Finding(
                    "inertial.mass_mismatch",
                    f"body '{name}': declared mass {m0:.6g} kg, its geoms give {m1:.6g} kg "
                    f"(tolerance {tol.mass_rtol:.1%})",
                    element="body",
                )
            )
        off = float(np.linalg.norm(c0 - c1))
        if off > tol.com_tol:
            out.append(
                Finding(
                    "inertial.com_mismatch",
                    f"body '{name}': declared centre of mass {np.round(c0, 4).tolist()} m is {off * 1e3:.1f} mm "
                    f"from its geoms' {np.round(c1, 4).tolist()} m (tolerance {tol.com_tol * 1e3:g} mm)",
                    element="body",
                )
            )
        outside = _hull_margin(model, b, c0)
        if not np.isfinite(outside) and m0 > 0:
            out.append(
                Finding(
                    "inertial.com_outside",
                    f"body '{name}': declares {m0:.6g} kg but has no parts (solid geoms) to carry it",
                    element="body",
                )
            )
        elif outside > tol.com_tol:
            out.append(
                Finding(
                    "inertial.com_outside",
                    f"body '{name}': declared centre of mass {np.round(c0, 4).tolist()} m lies "
                    f"{outside * 1e3:.1f} mm outside its geometry's convex hull",
                    element="body",
                )
            )
        if np.max(np.abs(i0 - i1)) > tol.inertia_rtol * scale:
            out.append(
                Finding(
                    "inertial.inertia_mismatch",
                    f"body '{name}': declared inertia diag {np.round(np.diag(i0), 9).tolist()} kg m^2, its geoms "
                    f"give {np.round(np.diag(i1), 9).tolist()} kg m^2 (tolerance {tol.inertia_rtol:.0%} of the "
                    "largest moment)",
                    element="body",
                )
            )
    return out
