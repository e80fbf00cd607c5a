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
            sha256="5f16304fb3aebc199092a6f474ba63857bba2829cbb6cdef8ddd9540b9e03b85",
            quick_score=0.815564973125,
            files=((".", "solutions/reference"),),
        ),
        Solution(
            "baseline/bad_mount",
            sha256="b47614d3ed5787fb4e8ef2c4e1d847cf0f3f0e50c5862835b914422bdc70ef9a",
            quick_score=0.15,
            base="reference",
            files=(("robot.xml", "solutions/baseline/bad_mount/robot.xml"),),
        ),
        Solution(
            "baseline/non_catalog_profile",
            sha256="1039fa5e2461c48d72bc2106d5674c07870b2fe706e692c4a4a9cd15450f7b63",
            quick_score=0.15,
            base="reference",
            transforms=(non_catalog_rail,),
        ),
        Solution(
            "baseline/raising_controller",
            sha256="05f237297bec48aa150387d7f2d5448dabd37164d652d26303375e143c957eed",
            quick_score=0.15,
            base="reference",
            files=(("controller.py", "solutions/baseline/raising_controller/controller.py"),),
        ),
        Solution(
            "baseline/tall_narrow",
            sha256="8db3deb2857b0e5e899a8e6e7e8d141ca38316287811afd14cd35c02bd4d8acb",
            quick_score=0.15,
            base="reference",
            files=(("robot.xml", "solutions/baseline/tall_narrow/robot.xml"),),
        ),
    ),
)
