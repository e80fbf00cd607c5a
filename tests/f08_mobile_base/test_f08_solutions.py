"""Family 08's committed frames and workspace skeleton are what the build-time generator writes."""

from __future__ import annotations

import mujoco

from rle_tasks.core.registry import get_task
from rle_tasks.f08_mobile_base.solutions.design_gen import generated_files
from rle_tasks.f08_mobile_base.task import SKELETON


def test_generator_reproduces_the_committed_frames_and_the_skeleton():
    files = generated_files()
    assert SKELETON in files and len(files) == 4
    for path, text in files.items():
        assert path.read_text() == text, (
            f"{path} is stale: python -m rle_tasks.f08_mobile_base.solutions.design_gen"
        )


def test_workspace_skeleton_is_the_asset_and_has_one_example_profile(tmp_path):
    get_task("08-mobile-base").make_dev_env(tmp_path)
    text = (tmp_path / "skeleton_robot.xml").read_text()
    assert text == SKELETON.read_text()
    m = mujoco.MjModel.from_xml_string(text)
    profiles = [m.geom(i).name for i in range(m.ngeom) if m.geom(i).name.startswith("profile_")]
    assert profiles == ["profile_4040_rail_left"]
    assert m.site("arm_mount_site").id >= 0
