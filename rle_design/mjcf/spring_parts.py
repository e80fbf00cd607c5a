"""Springs as parts: each MJCF spring is a catalog spring, loaded within its rating.

An ideal spring costs nothing in a model: any stiffness, any free length, any tension. A spring that
can be bought has a rate, a largest force (or moment) and a mass. This module matches every spring of
a compiled model to the spring catalogs and checks it over a set of poses:

* a stiff spatial tendon is a compression spring worked in tension by a cable through its coil
  (``springs.yaml``): its ``stiffness`` equals one entry's ``rate``; the cable only pulls, so the
  tendon length never falls below the lower ``springlength`` (where MuJoCo's spring would push); the
  tension ``k (L - springlength_upper)`` never exceeds the entry's ``max_force``;
* a stiff hinge joint carries a torsion spring (``torsion_springs.yaml``): its ``stiffness`` equals
  one entry's ``rate`` and the deflection ``|q - springref|`` over the joint's range never exceeds the
  entry's ``max_angle``;
* every matched spring's catalog mass counts towards the device (``spring_mass``).

Springs in parallel are separate tendons (or are refused: a doubled rate is not an entry).
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from rle_design.catalog import Spring, TorsionSpring, load_catalog

__all__ = [
    "RATE_TOL",
    "SpringPart",
    "SpringRatingFault",
    "match_rate",
    "spring_mass",
    "spring_parts",
    "spring_rating_faults",
]

RATE_TOL = 1e-6
"""Relative tolerance of a rate match [1]: the catalog's six significant digits, written as given."""
_PUSH_TOL = 1e-6  # tendon length below the lower spring length that counts as pushing [m]
OBJ = mujoco.mjtObj


@dataclass(frozen=True)
class SpringPart:
    """One spring of a model and the catalog entry it is, if any.

    Attributes:
        kind: ``"tendon"`` or ``"joint"``.
        index: Tendon or joint id.
        name: Its MJCF name.
        stiffness: Modelled stiffness [N/m or N m/rad].
        entry: The matching catalog entry, or None.
    """

    kind: str
    index: int
    name: str
    stiffness: float
    entry: Spring | TorsionSpring | None


@dataclass(frozen=True)
class SpringRatingFault:
    """A spring that is no catalog part, or is loaded beyond its rating.

    Attributes:
        code: ``"catalog"`` (no entry has its rate), ``"push"`` (the cable would have to push) or
            ``"overload"`` (tension above ``max_force``, or deflection above ``max_angle``).
        message: A sentence naming the spring, the entry and the first pose.
        pose: Index of the first pose at fault, or -1.
    """

    code: str
    message: str
    pose: int = -1


def _name(model: mujoco.MjModel, kind: mujoco.mjtObj, i: int) -> str:
    return mujoco.mj_id2name(model, kind, i) or f"{kind.name[6:].lower()}{i}"


def match_rate(kind: str, rate: float) -> Spring | TorsionSpring | None:
    """The catalog entry whose rate equals ``rate`` within ``RATE_TOL`` (``kind``: ``"springs"`` or
    ``"torsion_springs"``), else None."""
    for e in load_catalog(kind):
        if abs(rate - e.rate) <= RATE_TOL * e.rate:
            return e
    return None


def _nearest(kind: str, rate: float, unit: str) -> str:
    entries = sorted(load_catalog(kind), key=lambda e: abs(np.log(e.rate / rate)))[:3]
    return ", ".join(f"{e.id} ({e.rate:g} {unit})" for e in entries)


def spring_parts(model: mujoco.MjModel) -> list[SpringPart]:
    """Every stiff tendon and joint of ``model`` with its catalog entry (None when none matches)."""
    out = []
    for t in range(model.ntendon):
        k = float(model.tendon_stiffness[t])
        if k > 0:
            out.append(
                SpringPart("tendon", t, _name(model, OBJ.mjOBJ_TENDON, t), k, match_rate("springs", k))
            )
    for j in range(model.njnt):
        k = float(model.jnt_stiffness[j])
        if k > 0:
            hinge = int(model.jnt_type[j]) == int(mujoco.mjtJoint.mjJNT_HINGE)
            entry = match_rate("torsion_springs", k) if hinge else None
            out.append(SpringPart("joint", j, _name(model, OBJ.mjOBJ_JOINT, j), k, entry))
    return out


def spring_mass(model: mujoco.MjModel) -> float:
    """Catalog mass of the model's matched springs [kg] (their bodies are not modelled)."""
    return float(sum(p.entry.mass for p in spring_parts(model) if p.entry is not None))


def spring_rating_faults(model: mujoco.MjModel, poses: np.ndarray) -> list[SpringRatingFault]:
    """Springs that are not catalog parts, whose cable would push, or that are overloaded.

    Args:
        model: Compiled model (not modified).
        poses: Joint positions, shape (N, nq) [rad]; tendon checks use them, torsion checks use the
            joint's range (the whole range is reachable).
    """
    out: list[SpringRatingFault] = []
    parts = spring_parts(model)
    lengths = None
    if any(p.kind == "tendon" and p.entry is not None for p in parts) and len(poses):
        data = mujoco.MjData(model)
        lengths = np.empty((len(poses), model.ntendon))
        for i, q in enumerate(np.asarray(poses, float)):
            data.qpos[:] = q
            mujoco.mj_kinematics(model, data)
            mujoco.mj_comPos(model, data)
            mujoco.mj_tendon(model, data)
            lengths[i] = data.ten_length
    for p in parts:
        if p.kind == "tendon":
            if p.entry is None:
                out.append(
                    SpringRatingFault(
                        "catalog",
                        f"spring '{p.name}': stiffness {p.stiffness:g} N/m is no catalog spring's rate "
                        f"(nearest: {_nearest('springs', p.stiffness, 'N/m')}); springs in parallel are "
                        "separate tendons",
                    )
                )
                continue
            if lengths is None:
                continue
            lo, hi = (float(x) for x in model.tendon_lengthspring[p.index])
            length = lengths[:, p.index]
            pushing = np.flatnonzero(length < lo - _PUSH_TOL)
            if pushing.size:
                i = int(pushing[0])
                out.append(
                    SpringRatingFault(
                        "push",
                        f"spring '{p.name}' ({p.entry.id}): at pose {i} its length {length[i] * 1e3:.1f} mm "
                        f"is below its spring length {lo * 1e3:.1f} mm, where the model pushes; a cable "
                        'only pulls (use springlength="0 L0" for a spring that goes slack)',
                        i,
                    )
                )
            tension = p.stiffness * np.maximum(length - hi, 0.0)
            over = np.flatnonzero(tension > p.entry.max_force)
            if over.size:
                i = int(np.argmax(tension))
                out.append(
                    SpringRatingFault(
                        "overload",
                        f"spring '{p.name}' ({p.entry.id}): tension {tension[i]:.1f} N at pose {i} exceeds "
                        f"its {p.entry.max_force:g} N rating (stroke {p.entry.max_stroke * 1e3:.0f} mm)",
                        i,
                    )
                )
        else:
            if p.entry is None:
                kind = (
                    "hinge"
                    if int(model.jnt_type[p.index]) == int(mujoco.mjtJoint.mjJNT_HINGE)
                    else "non-hinge"
                )
                out.append(
                    SpringRatingFault(
                        "catalog",
                        f"joint '{p.name}': stiffness {p.stiffness:g} is no torsion spring's rate "
                        + (
                            f"(nearest: {_nearest('torsion_springs', p.stiffness, 'N m/rad')})"
                            if kind == "hinge"
                            else "(only hinge joints can carry a torsion spring)"
                        ),
                    )
                )
                continue
            ref = float(model.qpos_spring[model.jnt_qposadr[p.index]])
            if not model.jnt_limited[p.index]:
                out.append(
                    SpringRatingFault(
                        "overload",
                        f"joint '{p.name}' ({p.entry.id}): the joint has no range, so the torsion spring's "
                        f"deflection is unbounded (rating {p.entry.max_angle:g} rad)",
                    )
                )
                continue
            lo, hi = (float(x) for x in model.jnt_range[p.index])
            worst = max(abs(lo - ref), abs(hi - ref))
            if worst > p.entry.max_angle:
                out.append(
                    SpringRatingFault(
                        "overload",
                        f"joint '{p.name}' ({p.entry.id}): deflection up to {worst:.3f} rad from springref "
                        f"{ref:.3f} rad over the joint range exceeds its {p.entry.max_angle:g} rad rating "
                        f"({p.entry.max_moment:g} N m)",
                    )
                )
    return out
