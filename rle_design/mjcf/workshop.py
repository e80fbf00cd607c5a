"""What a workshop would check before building a design: no part inside another, mass where the
material is, parts strong enough. One entry point, ``workshop_findings``, for verifiers and for the
public helpers that agents run before they submit.

Rules and codes (``Finding.code``):

* ``interpenetration.weld``: an audited part shares material with a part welded to it (MuJoCo never
  collides them) beyond ``WorkshopRules.weld_share`` of the smaller part (a seat); ``interpenetration.joint``: with the part
  across a joint (parent/child, also skipped by MuJoCo), beyond the stock joint's own overlap
  (``rle_design.mjcf.interpenetration``), at the zero pose or a given pose;
* ``material.density``, ``inertial.*``: ``rle_design.mjcf.material_mass``;
* ``strength.overstressed``, ``strength.too_flexible``: ``rle_design.mjcf.strength``.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field

import mujoco
import numpy as np

from rle_design.catalog import Material, load_catalog
from rle_design.mjcf.contract import Finding
from rle_design.mjcf.geom_solid import geom_volume
from rle_design.mjcf.interpenetration import find_overlaps
from rle_design.mjcf.material_mass import InertialTolerance, geom_masses, material_findings, material_for
from rle_design.mjcf.strength import part_loads, spring_tensions, strength_faults

__all__ = ["WorkshopRules", "workshop_findings"]


@dataclass(frozen=True)
class WorkshopRules:
    """A family's thresholds (each derived in its README).

    Attributes:
        joint_tol: Collision-geometry penetration accepted across a joint [m].
        weld_tol: Penetration accepted between welded parts [m].
        shared_volume: Shared material beyond the baseline that still counts as touching [m^3].
        weld_share: Fraction of the smaller part's volume welded parts may share (a seat) [1].
        inertial: Inertial tolerances.
        materials: Material ids a part may be made of; None: no density rule.
        massless_ok: Whether geoms declared massless are allowed.
        dynamic_factor: Weights are multiplied by this for the strength check [1].
        safety_factor: Material id -> factor on its yield strength [1].
        deflection_ratio: Allowed deflection per metre of span [1].
        join_tol: Largest gap between joined parts [m].
        strength: Whether the strength rule runs.
    """

    joint_tol: float
    weld_tol: float
    shared_volume: float
    weld_share: float = 0.0
    inertial: InertialTolerance = InertialTolerance()
    materials: tuple[str, ...] | None = ()
    massless_ok: bool = True
    dynamic_factor: float = 2.0
    safety_factor: dict[str, float] = field(default_factory=dict)
    deflection_ratio: float = 0.02
    join_tol: float = 1e-3
    strength: bool = True

    def catalog_materials(self) -> list[Material] | None:
        if self.materials is None:
            return None
        cat = load_catalog("materials")
        return [cat.get(m) for m in self.materials] if self.materials else list(cat)


def workshop_findings(
    spec: mujoco.MjSpec,
    model: mujoco.MjModel,
    bodies: Iterable[int],
    rules: WorkshopRules,
    *,
    poses: np.ndarray | None = None,
    baseline: Iterable[int] = (),
    fused: Iterable[int] = (),
    joint_poses: bool = True,
) -> list[Finding]:
    """Every workshop finding for the audited bodies of a compiled design.

    Args:
        spec: The design's spec (not modified).
        model: Its compiled model.
        bodies: Ids of the bodies a submission adds or changes.
        rules: The family's thresholds.
        poses: Joint positions for the across-joint test and the worst spring tension, shape (N, nq)
            [rad]; None: ``qpos0`` only.
        baseline: Stock bodies whose joints' own overlap is allowed.
        fused: Audited bodies printed as one part (their welded overlaps are one part's material).
        joint_poses: Test across-joint pairs at ``poses`` (False: at ``qpos0`` only).
    """
    bodies = [int(b) for b in bodies]
    out: list[Finding] = []
    overlaps = find_overlaps(
        model,
        bodies,
        poses if joint_poses else None,
        joint_tol=rules.joint_tol,
        weld_tol=rules.weld_tol,
        fused=fused,
        baseline=baseline,
        volume_tol=rules.shared_volume,
        weld_share=rules.weld_share,
        first_per_pose=True,
    )
    for o in overlaps:
        code = "interpenetration.joint" if o.across_joint else "interpenetration.weld"
        out.append(Finding(code, o.message, element="geom"))
    materials = rules.catalog_materials()
    out += material_findings(
        spec, model, bodies, materials=materials, tol=rules.inertial, massless_ok=rules.massless_ok
    )
    if rules.strength and materials is not None:
        masses = geom_masses(spec, model)

        def material_of(g: int) -> Material | None:
            vol = geom_volume(model, g)
            return material_for(masses[g] / vol, materials) if vol > 0 else None

        tensions = spring_tensions(model, poses if poses is not None else model.qpos0[None, :])
        loads = part_loads(
            model,
            bodies,
            masses=masses,
            material_of=material_of,
            tensions=tensions,
            dynamic_factor=rules.dynamic_factor,
            safety_factor=lambda m: rules.safety_factor.get(m.id, 1.0),
            deflection_ratio=rules.deflection_ratio,
            join_tol=rules.join_tol,
        )
        out += [Finding(f"strength.{f.code}", f.message, element="geom") for f in strength_faults(loads)]
    return out
