"""MJCF loading, composition, audits, meshes, printability and catalog matching."""

from rle_design.mjcf.audit import BodyAudit, ModelAudit, audit_model
from rle_design.mjcf.catalog_match import ProfileReport, ProfileUse, match_profiles
from rle_design.mjcf.contract import Finding, ModelContract, check_contract
from rle_design.mjcf.loader import Design, LoadLimits, load_design
from rle_design.mjcf.mesh import (
    MeshProperties,
    WallThickness,
    boolean,
    collision_hulls,
    compare_inertial,
    mesh_properties,
    min_wall_thickness,
)
from rle_design.mjcf.printability import PrintabilityReport, printability_report

__all__ = [
    "BodyAudit",
    "Design",
    "Finding",
    "LoadLimits",
    "MeshProperties",
    "ModelAudit",
    "ModelContract",
    "PrintabilityReport",
    "ProfileReport",
    "ProfileUse",
    "WallThickness",
    "audit_model",
    "boolean",
    "check_contract",
    "collision_hulls",
    "compare_inertial",
    "load_design",
    "match_profiles",
    "mesh_properties",
    "min_wall_thickness",
    "printability_report",
]
