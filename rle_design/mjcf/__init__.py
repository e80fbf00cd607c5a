"""MJCF loading, composition, audits, meshes, printability and catalog matching."""
