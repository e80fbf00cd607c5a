"""Strength of added parts: each prismatic part as a cantilever clamped where it meets its support.

Structure. The audited bodies' solid geoms (parts) that touch (surface gap <= ``join_tol``, MuJoCo's
``mj_geomDistance`` at ``qpos0``) form a tree, rooted at the parts that touch a geom of a body that
is not audited (the support: a stock link, a frame). Each part is clamped at its nearest point to
its tree parent and carries everything beyond it: its own weight and the weight of every part
further out (at their centroids), times ``dynamic_factor``, and the worst tension of every spring
whose end sits on one of those parts.

Sections. Each part is a beam of the cross-sections ``sections`` gives (a primitive's constant
section; a mesh cut into ``MESH_SECTIONS`` slices).

Loads, bounded for any pose. For a force F at lever r from the clamp (r = |r|, rho its distance from
the beam axis) the bending moment is at most F r and the torsion at most F rho; the axial force at
most F. Stress: von Mises sqrt((M c / I + N / A)^2 + 3 tau^2) against the material's yield strength
over ``safety_factor``. Deflection of the clamp's far end under the static loads (dynamic factor 1),
span L: a transverse force F at a <= L gives F a^2 (3 L - a) / (6 E I) (a tip load: F L^3 / 3 E I),
beyond the end (a > L) F L^3 / (3 E I) + F (a - L) L^2 / (2 E I); the limit is
``deflection_ratio`` x L.

SI units: N, m, Pa, kg.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Iterable
from dataclasses import dataclass

import mujoco
import numpy as np

from rle_design.catalog import Material
from rle_design.mjcf.sections import Section, beam_section, mesh_sections

__all__ = ["PartLoad", "StrengthFault", "part_loads", "spring_tensions", "strength_faults"]

G = 9.81
"""Gravitational acceleration [m/s^2]."""
_GT = mujoco.mjtGeom


@dataclass(frozen=True)
class PartLoad:
    """What one part carries and what it can bear.

    Attributes:
        part: Geom name.
        body: Its body's name.
        material: Material id.
        span: Beam length from the clamp to its far end [m].
        load: Sum of the forces it carries, dynamic factor applied [N].
        moment: Bending-moment bound at the clamp [N m].
        stress: von Mises stress bound at the clamp [Pa].
        allowable: Yield strength over the safety factor [Pa].
        deflection: Far-end deflection under the static loads [m].
        deflection_limit: Allowed deflection [m].
    """

    part: str
    body: str
    material: str
    span: float
    load: float
    moment: float
    stress: float
    allowable: float
    deflection: float
    deflection_limit: float


@dataclass(frozen=True)
class StrengthFault:
    """A part that yields (``code == "overstressed"``) or sags too far (``"too_flexible"``)."""

    code: str
    part: PartLoad

    @property
    def message(self) -> str:
        p = self.part
        if self.code == "overstressed":
            return (
                f"part '{p.part}' of body '{p.body}' ({p.material}, {p.span * 1e3:.0f} mm span) carries "
                f"{p.load:.3g} N: bending moment {p.moment:.3g} N m gives {p.stress / 1e6:.1f} MPa at its "
                f"clamp, allowable {p.allowable / 1e6:.1f} MPa"
            )
        return (
            f"part '{p.part}' of body '{p.body}' ({p.material}, {p.span * 1e3:.0f} mm span) sags "
            f"{p.deflection * 1e3:.2f} mm under its static load, limit {p.deflection_limit * 1e3:.2f} mm"
        )


def spring_tensions(model: mujoco.MjModel, poses: np.ndarray) -> np.ndarray:
    """Largest tension of each tendon spring over ``poses`` (shape (N, nq), rad) [N], the cable only
    pulling: ``k max(L - springlength_upper, 0)``, and ``k max(springlength_lower - L, 0)`` never
    counts (a cable cannot push)."""
    out = np.zeros(model.ntendon)
    if model.ntendon == 0 or len(poses) == 0:
        return out
    data = mujoco.MjData(model)
    for q in np.asarray(poses, float):
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        mujoco.mj_tendon(model, data)
        stretch = np.maximum(data.ten_length - model.tendon_lengthspring[:, 1], 0.0)
        out = np.maximum(out, model.tendon_stiffness * stretch)
    return out


def _spring_ends(model: mujoco.MjModel, tension: np.ndarray) -> list[tuple[int, np.ndarray, float]]:
    """(site id, position in its body [m], tension [N]) of each end of each tensioned spatial tendon."""
    ends = []
    for t in range(model.ntendon):
        if tension[t] <= 0:
            continue
        adr, num = int(model.tendon_adr[t]), int(model.tendon_num[t])
        for w in range(adr, adr + num):
            if int(model.wrap_type[w]) == int(mujoco.mjtWrap.mjWRAP_SITE):
                ends.append((int(model.wrap_objid[w]), float(tension[t])))
    return [(s, model.site_pos[s].copy(), f) for s, f in ends]


def _name(model, kind, i: int) -> str:
    return mujoco.mj_id2name(model, kind, i) or f"{kind.name[6:].lower()}{i}"


def part_loads(
    model: mujoco.MjModel,
    bodies: Iterable[int],
    *,
    masses: np.ndarray,
    material_of: Callable[[int], Material | None],
    tensions: np.ndarray | None = None,
    dynamic_factor: float,
    safety_factor: Callable[[Material], float],
    deflection_ratio: float,
    join_tol: float,
) -> list[PartLoad]:
    """Load, stress and deflection of every beam part of the audited bodies.

    Args:
        model: Compiled model, measured at ``qpos0``.
        bodies: Ids of the audited bodies (the added parts' bodies).
        masses: Mass of each geom [kg] (``material_mass.geom_masses``).
        material_of: Geom id -> its catalog material (None: not analysed).
        tensions: Worst tension of each tendon [N] (``spring_tensions``); None: no springs.
        dynamic_factor: Multiplier on weights for the strength check [1].
        safety_factor: Material -> factor on its yield strength [1].
        deflection_ratio: Allowed far-end deflection per metre of span [1].
        join_tol: Largest surface gap between parts that are joined [m].
    """
    audited = set(int(b) for b in bodies)
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    solid = [
        g for g in range(model.ngeom) if int(model.geom_type[g]) not in (_GT.mjGEOM_PLANE, _GT.mjGEOM_HFIELD)
    ]
    parts = [g for g in solid if int(model.geom_bodyid[g]) in audited]
    support = [g for g in solid if int(model.geom_bodyid[g]) not in audited]
    weld = model.body_weldid
    fromto = np.zeros(6)

    def touch(a: int, b: int) -> np.ndarray | None:
        if weld[model.geom_bodyid[a]] != weld[model.geom_bodyid[b]]:
            return None
        if (
            np.linalg.norm(data.geom_xpos[a] - data.geom_xpos[b])
            > model.geom_rbound[a] + model.geom_rbound[b] + join_tol
        ):
            return None
        if mujoco.mj_geomDistance(model, data, a, b, 1.0, fromto) > join_tol:
            return None
        return fromto[:3].copy()  # the point on ``a``

    clamp: dict[int, np.ndarray] = {}
    parent: dict[int, int] = {}
    queue: deque[int] = deque()
    for g in parts:
        for s in support:
            p = touch(g, s)
            if p is not None:
                clamp[g], parent[g] = p, -1
                queue.append(g)
                break
    while queue:
        g = queue.popleft()
        for h in parts:
            if h not in clamp:
                p = touch(h, g)
                if p is not None:
                    clamp[h], parent[h] = p, g
                    queue.append(h)
    children: dict[int, list[int]] = {g: [] for g in clamp}
    for g, p in parent.items():
        if p >= 0:
            children[p].append(g)
    ends = _spring_ends(model, tensions) if tensions is not None else []
    spring_at: dict[int, list[tuple[np.ndarray, float]]] = {}
    for site, _, force in ends:
        b = int(model.site_bodyid[site])
        if b not in audited:
            continue
        near = [g for g in clamp if int(model.geom_bodyid[g]) == b] or list(clamp)
        if not near:
            continue
        x = data.site_xpos[site]
        g = min(near, key=lambda k: np.linalg.norm(data.geom_xpos[k] - x))
        spring_at.setdefault(g, []).append((x.copy(), force))

    def subtree(g: int) -> list[int]:
        out, stack = [], [g]
        while stack:
            k = stack.pop()
            out.append(k)
            stack += children[k]
        return out

    out: list[PartLoad] = []
    cache: dict = {}
    for g in clamp:
        mat = material_of(g)
        if mat is None:
            continue
        rot = data.geom_xmat[g].reshape(3, 3)
        beam = beam_section(int(model.geom_type[g]), model.geom_size[g])
        if beam is not None:
            lo, hi = -beam.length / 2, beam.length / 2
            local_axis = beam.axis
        elif int(model.geom_type[g]) == int(_GT.mjGEOM_MESH):
            local_axis, (lo, hi), sections = mesh_sections(model, g, cache=cache)
            if not sections:
                continue
        else:
            continue  # spheres and ellipsoids are masses, not beams
        axis = rot @ local_axis
        # the clamp section: the point of contact projected onto the beam's axis
        s0 = float(np.clip((clamp[g] - data.geom_xpos[g]) @ axis, lo, hi))
        far = hi if hi - s0 >= s0 - lo else lo
        span = abs(far - s0)
        root = data.geom_xpos[g] + s0 * axis
        if beam is not None:  # prismatic: the clamp section is the weakest
            sections = [Section(s0, local_axis * s0, beam.area, beam.inertia, beam.bending, beam.torsion)]
        else:
            sections = [c for c in sections if (c.s - s0) * (far - s0) >= 0]  # between clamp and far end
        others = [(data.geom_xpos[k].copy(), masses[k] * G, True) for k in subtree(g) if k != g]
        others += [(x, f, False) for k in subtree(g) for x, f in spring_at.get(k, [])]
        own = masses[g] * G
        stress = moment_max = 0.0
        for sec in sections:
            centre = data.geom_xpos[g] + rot @ sec.centre
            beyond = abs(far - sec.s) / span if span > 0 else 0.0  # share of the part beyond it
            own_at = data.geom_xpos[g] + axis * (sec.s + far) / 2 if beam is None else data.geom_xpos[g]
            loads = others + [(own_at, own * (beyond if beam is None else 1.0), True)]
            moment = torsion = axial = 0.0
            for x, f, weight in loads:
                r = x - centre
                fd = f * (dynamic_factor if weight else 1.0)
                moment += fd * float(np.linalg.norm(r))
                torsion += fd * float(np.linalg.norm(r - (r @ axis) * axis))
                axial += fd
            sigma = moment * sec.bending + axial / sec.area
            sec_stress = float(np.sqrt(sigma**2 + 3 * (torsion * sec.torsion) ** 2))
            if sec_stress >= stress:
                stress, moment_max = sec_stress, moment
        # sag of the far end under the static loads, the weakest section over the whole span
        ei = mat.youngs_modulus * min(sec.inertia for sec in sections)
        deflection = 0.0
        total = 0.0
        for x, f, weight in others + [(data.geom_xpos[g], own, True)]:
            a = float(np.linalg.norm(x - root))
            total += f * (dynamic_factor if weight else 1.0)
            if a <= span:
                deflection += f * a**2 * (3 * span - a) / (6 * ei)
            else:
                deflection += f * span**3 / (3 * ei) + f * (a - span) * span**2 / (2 * ei)
        out.append(
            PartLoad(
                _name(model, mujoco.mjtObj.mjOBJ_GEOM, g),
                _name(model, mujoco.mjtObj.mjOBJ_BODY, int(model.geom_bodyid[g])),
                mat.id,
                span,
                total,
                moment_max,
                stress,
                mat.yield_strength / safety_factor(mat),
                deflection,
                deflection_ratio * span,
            )
        )
    return out


def strength_faults(loads: Iterable[PartLoad]) -> list[StrengthFault]:
    """Parts whose stress exceeds the allowable or whose deflection exceeds the limit."""
    out = []
    for p in loads:
        if p.stress > p.allowable:
            out.append(StrengthFault("overstressed", p))
        if p.deflection > p.deflection_limit:
            out.append(StrengthFault("too_flexible", p))
    return out
