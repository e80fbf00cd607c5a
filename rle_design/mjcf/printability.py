"""FDM printability of a part mesh against the rules in ``catalogs/materials.yaml`` (``print_rules``).

Checks (all in metres, mesh units taken as metres):

- watertight: a closed surface (slicers need one; volume and mass are meaningless otherwise);
- minimum wall: ``mesh.min_wall_thickness`` (inward rays from seeded surface samples) >= ``min_wall``;
- build volume: the part's axis-aligned extents fit ``build_volume`` in at least one of the six
  axis-aligned "up" directions (the two horizontal extents may be swapped);
- overhang: area fraction of faces that point downward more steeply than ``max_overhang_deg`` from
  vertical (normal within ``90 - max_overhang_deg`` degrees of straight down), excluding faces lying
  on the bed (all vertices within one ``layer_height`` of the lowest point). The orientation reported
  is the fitting one with the least overhang; the part fails when that fraction exceeds
  ``max_overhang_fraction`` (support material everywhere is a design smell, cavity ceilings are
  bridged and stay below it).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from rle_design.catalog import load_catalog
from rle_design.mjcf.mesh import as_trimesh, min_wall_thickness

if TYPE_CHECKING:
    import trimesh

__all__ = ["PrintabilityReport", "printability_report", "overhang_fraction"]

_UPS = {
    "+x": (1.0, 0.0, 0.0),
    "-x": (-1.0, 0.0, 0.0),
    "+y": (0.0, 1.0, 0.0),
    "-y": (0.0, -1.0, 0.0),
    "+z": (0.0, 0.0, 1.0),
    "-z": (0.0, 0.0, -1.0),
}


@dataclass(frozen=True)
class PrintabilityReport:
    """Result of ``printability_report``.

    Attributes:
        material: Material id (``catalogs/materials.yaml``).
        mass: Solid mass at the material's bulk density [kg] (0 when not watertight).
        watertight: Closed surface.
        min_wall: Smallest sampled wall thickness [m].
        min_wall_rule: Required minimum wall [m].
        extents: Axis-aligned size of the part as given (x, y, z) [m].
        build_volume: Printer build volume (x, y, z) [m].
        fits: Fits the build volume in at least one axis-aligned orientation.
        up: Chosen up direction of the part (``"+z"`` ...) or "" when none fits.
        overhang_fraction: Overhang area / total area in the chosen orientation.
        max_overhang_deg: Largest unsupported overhang from vertical [deg].
        passed: All checks passed.
        reasons: Why it failed (empty when passed).
    """

    material: str
    mass: float
    watertight: bool
    min_wall: float
    min_wall_rule: float
    extents: tuple[float, float, float]
    build_volume: tuple[float, float, float]
    fits: bool
    up: str
    overhang_fraction: float
    max_overhang_deg: float
    passed: bool
    reasons: tuple[str, ...]


def overhang_fraction(mesh: trimesh.Trimesh, up, max_overhang_deg: float, bed_tol: float) -> float:
    """Area fraction of overhanging faces for build direction ``up`` (bed faces excluded).

    Args:
        mesh: Part mesh [m].
        up: Build direction (3,), unit vector.
        max_overhang_deg: Largest unsupported overhang from vertical [deg].
        bed_tol: Height above the lowest point within which a face lies on the bed [m].
    """
    up = np.asarray(up, dtype=float)
    heights = mesh.vertices @ up
    on_bed = (heights[mesh.faces] <= heights.min() + bed_tol).all(axis=1)
    downness = -(mesh.face_normals @ up)  # cos of the angle between the normal and straight down
    steep = downness > np.cos(np.radians(90.0 - max_overhang_deg)) + 1e-12
    area = mesh.area_faces
    return float(area[steep & ~on_bed].sum() / area.sum())


def _fits(extents: np.ndarray, up_axis: int, volume: np.ndarray) -> bool:
    horiz = sorted(np.delete(extents, up_axis))
    return extents[up_axis] <= volume[2] and horiz[0] <= min(volume[:2]) and horiz[1] <= max(volume[:2])


def printability_report(
    mesh, material: str = "pla", n_samples: int = 2000, seed: int = 0, max_overhang_fraction: float = 0.25
) -> PrintabilityReport:
    """Check a part against the FDM print rules of the materials catalog.

    Args:
        mesh: ``trimesh.Trimesh`` or mesh file path [m].
        material: Material id from ``catalogs/materials.yaml`` (density for the mass).
        n_samples: Surface samples for the wall-thickness rays.
        seed: Sampling seed.
        max_overhang_fraction: Largest accepted overhang area fraction.
    """
    catalog = load_catalog("materials")
    mat = catalog.get(material)
    rules = catalog.extra["print_rules"]
    min_wall_rule = float(rules["min_wall"])
    max_deg = float(rules["max_overhang_deg"])
    volume = np.asarray(rules["build_volume"], dtype=float)
    part = as_trimesh(mesh)
    reasons = []

    watertight = bool(part.is_watertight)
    if not watertight:
        reasons.append("mesh is not watertight (open or non-manifold surface)")
    wall = min_wall_thickness(part, n_samples=n_samples, seed=seed).minimum
    if wall < min_wall_rule:
        reasons.append(f"minimum wall {wall * 1e3:.3f} mm < {min_wall_rule * 1e3:.3f} mm")

    extents = np.asarray(part.extents, dtype=float)
    best_up, best_frac = "", 1.0
    for name, up in _UPS.items():
        if not _fits(extents, int(np.argmax(np.abs(up))), volume):
            continue
        frac = overhang_fraction(part, up, max_deg, float(rules["layer_height"]))
        if not best_up or frac < best_frac - 1e-12:
            best_up, best_frac = name, frac
    fits = bool(best_up)
    if not fits:
        dims = " x ".join(f"{e * 1e3:.1f}" for e in extents)
        vol = " x ".join(f"{v * 1e3:.0f}" for v in volume)
        reasons.append(
            f"part {dims} mm does not fit the build volume {vol} mm in any axis-aligned orientation"
        )
        best_frac = min(
            overhang_fraction(part, up, max_deg, float(rules["layer_height"])) for up in _UPS.values()
        )
    if best_frac > max_overhang_fraction:
        reasons.append(
            f"overhang beyond {max_deg:g} deg covers {best_frac:.1%} of the surface "
            f"(limit {max_overhang_fraction:.0%}) in the best orientation"
        )
    return PrintabilityReport(
        material=material,
        mass=float(part.volume * mat.density) if watertight else 0.0,
        watertight=watertight,
        min_wall=wall,
        min_wall_rule=min_wall_rule,
        extents=tuple(map(float, extents)),
        build_volume=tuple(map(float, volume)),
        fits=fits,
        up=best_up,
        overhang_fraction=best_frac,
        max_overhang_deg=max_deg,
        passed=not reasons,
        reasons=tuple(reasons),
    )
