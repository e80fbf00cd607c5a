"""Task ``03-pocket-cube``: the physical pocket cube (model, move model, state reading, distances,
score), the two-arm scene and metered environment, the verifier and the TaskSpec (``task_spec``).
See README.md.
"""

from rle_tasks.f03_physical_reasoning.cube.detent import CubeDetent
from rle_tasks.f03_physical_reasoning.cube.distance import distance_table, optimal_turns
from rle_tasks.f03_physical_reasoning.cube.lattice import CUBIES, FACES, MOVES, SOLVED, LatticeState
from rle_tasks.f03_physical_reasoning.cube.model import CubeConfig, cube_spec
from rle_tasks.f03_physical_reasoning.cube.reading import (
    CubePoses,
    CubeReading,
    check_solved,
    poses_from_data,
    read,
)
from rle_tasks.f03_physical_reasoning.cube.score import CubeScore, cube_reward
from rle_tasks.f03_physical_reasoning.cube.turns import Transition, classify, transitions

__all__ = [
    "CUBIES",
    "FACES",
    "MOVES",
    "SOLVED",
    "CubeConfig",
    "CubeDetent",
    "CubePoses",
    "CubeReading",
    "CubeScore",
    "LatticeState",
    "Transition",
    "check_solved",
    "classify",
    "cube_reward",
    "cube_spec",
    "distance_table",
    "optimal_turns",
    "poses_from_data",
    "read",
    "task_spec",
    "transitions",
]


def task_spec():
    """The TaskSpec of ``03-pocket-cube`` (``task.task_spec``; imported lazily)."""
    from rle_tasks.f03_physical_reasoning.cube.task import task_spec as spec

    return spec()
