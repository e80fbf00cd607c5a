"""The kitchen backend seam: the built-in kitchen implements it, and its stages agree with success."""

import numpy as np

from rle_tasks.envs.kitchen.backend import BuiltinKitchen, KitchenBackend
from rle_tasks.envs.kitchen.sessions import pretrain_seed


def test_builtin_kitchen_implements_the_backend_and_reports_stages():
    k = BuiltinKitchen(level=1, image_size=None)
    assert isinstance(k, KitchenBackend)
    obs = k.reset("PickPlaceCounterToDrawer", pretrain_seed(2), 5)
    assert obs["instruction"].startswith("Pick the ") and "objects" not in obs
    stages = k.stages()
    assert list(stages) == [c for c in stages] and len(stages) == 3
    assert stages[next(n for n in stages if n.startswith("gripper"))] is True
    assert k.success() is all(stages.values()) is False
    hold = np.zeros(12)
    hold[6] = hold[11] = -1.0
    obs = k.step(hold)
    assert obs["time"] > 0
