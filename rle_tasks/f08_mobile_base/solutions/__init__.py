"""Shipped solutions of 08-mobile-base, materialised by ``rle_tasks.core.solutions``.

Committed once: ``reference/{robot.xml, controller.py}`` (the frame written by ``design_gen.py``) and,
per baseline, only the file that differs. Each solution directory holds ``robot.xml`` and
``controller.py``.

- ``reference``: 4040 frame, adapter on a four-post tower, the planning controller.
- ``baseline/bad_mount``: long, low frame with the mount at the rear (``design_gen.BAD_MOUNT``).
- ``baseline/non_catalog_profile``: the reference with one rail renamed to a profile not in the catalog.
- ``baseline/raising_controller``: the reference frame with a controller that raises.
- ``baseline/tall_narrow``: small footprint, 0.75 m tower (``design_gen.TALL_NARROW``).

``SOLUTIONS`` is the one table of pinned checksums (``artifact_sha256`` of each materialised directory)
and golden scores (quick mode, public development key).
"""

from __future__ import annotations

from pathlib import Path

from lxml import etree

from rle_tasks.core.solutions import Solution, SolutionSet, edit_xml

NON_CATALOG_GEOM = "profile_5050_rail_left"
"""The renamed rail of ``baseline/non_catalog_profile`` (5050 is not a catalog profile)."""


def _rename_left_rail(root: etree._Element) -> None:
    geom = next(g for g in root.iter("geom") if g.get("name") == "profile_4040_rail_left")
    geom.set("name", NON_CATALOG_GEOM)


def non_catalog_rail(directory: Path) -> None:
    """Rename the left rail's profile id to ``5050`` (not in ``profiles.yaml``)."""
    edit_xml(directory / "robot.xml", _rename_left_rail)


SOLUTIONS = SolutionSet(
    package="rle_tasks.f08_mobile_base",
    solutions=(
        Solution(
            "reference",
            sha256="b60defce0cbb2a4e0e290b304bda9c6d6511fe8f5e707ff4a43d4d124661df55",
            quick_score=0.811911939216,
            files=((".", "solutions/reference"),),
        ),
        Solution(
            "baseline/bad_mount",
            sha256="e2cf5805fe9b85bf8c326d79985fc902127f29665f0661c6ae3dd4df1f4a7c55",
            quick_score=0.15,
            base="reference",
            files=(("robot.xml", "solutions/baseline/bad_mount/robot.xml"),),
        ),
        Solution(
            "baseline/non_catalog_profile",
            sha256="385eec11e56d97bc00f96a7666d3abf860d78e7ca4c1c35af29eba55febaa8c7",
            quick_score=0.15,
            base="reference",
            transforms=(non_catalog_rail,),
        ),
        Solution(
            "baseline/raising_controller",
            sha256="21f06cbe851758d1ac5139af9d0dece3a6f69e4944ffea8d0b224fedcf3ef810",
            quick_score=0.15,
            base="reference",
            files=(("controller.py", "solutions/baseline/raising_controller/controller.py"),),
        ),
        Solution(
            "baseline/tall_narrow",
            sha256="ccff3e505ec0c96e540a139697216e54ebbd77fc9a5d7b7928250708bc3bd1da",
            quick_score=0.15,
            base="reference",
            files=(("robot.xml", "solutions/baseline/tall_narrow/robot.xml"),),
        ),
    ),
)
