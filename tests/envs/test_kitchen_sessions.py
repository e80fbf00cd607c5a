"""The kitchen scene sets' action size, stated without building a scene, is the built scene's."""

from __future__ import annotations

from rle_design.ledger import SceneSet
from rle_tasks.envs.kitchen.sessions import GroupScenes, KitchenScenes


def test_stated_action_size_is_the_built_environments():
    for scenes in (
        KitchenScenes("OpenFridge", level=3, evaluation=None, image_size=None),
        GroupScenes("CloseDrawer", tasks=("CloseDrawer", "OpenDrawer"), image_size=None),
    ):
        assert scenes.action_size() == SceneSet.action_size(scenes) == 12
