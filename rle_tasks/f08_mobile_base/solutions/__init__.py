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
            sha256="ea645b60f38ad364579175e557e8420c935b80f6b52652996e5be2794e36779e",
            quick_score=0.811911939216,
            files=((".", "solutions/reference"),),
        ),
        Solution(
            "baseline/bad_mount",
            sha256="d9f740402a23c4c402a1a55a2cfac9418c17a3f43e8a9e67a643710e71ba3497",
            quick_score=0.15,
            base="reference",
            files=(("robot.xml", "solutions/baseline/bad_mount/robot.xml"),),
        ),
        Solution(
            "baseline/non_catalog_profile",
            sha256="0e094395f21de995c81f9a6051e5f47b84c0b81dd73f958ea7a14665d4e81d37",
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
            sha256="2c1fb82895539997a2dda3cb773b573bc1633b8d9efc5c92148a77a663e04b47",
            quick_score=0.15,
            base="reference",
            files=(("robot.xml", "solutions/baseline/tall_narrow/robot.xml"),),
        ),
    ),
)
