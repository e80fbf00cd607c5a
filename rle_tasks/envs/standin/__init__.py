"""Bimanual stand-in for RoboTwin 2.0 (family 05's RoboTwin tracks).

RoboTwin 2.0 cannot be installed here (assets from a model hub, SAPIEN, cuRobo from source), so the
two RoboTwin tracks run on this stand-in, built with the toolkit: two UR5e arms with parallel
grippers behind a table, three RoboTwin-style two-arm tasks, scripted experts, and the card's
interface (16-D state, 14-D joint targets, two 128 x 128 views). Everything that shows it names it
a stand-in.
"""

from rle_tasks.envs.standin.env import ACTION_DIM, STATE_DIM, VIEW, StandinEnv
from rle_tasks.envs.standin.scene import CLEAN, SceneLook, robust_look
from rle_tasks.envs.standin.tasks import TASKS, StandinTask

__all__ = [
    "ACTION_DIM",
    "CLEAN",
    "STATE_DIM",
    "TASKS",
    "VIEW",
    "SceneLook",
    "StandinEnv",
    "StandinTask",
    "robust_look",
]
