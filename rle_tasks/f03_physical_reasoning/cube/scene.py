"""The ``03-pocket-cube`` scene: two Pandas facing each other, the scrambled cube on a stand, one camera.

Frame: world z up, table top at ``TABLE.top_z`` = 0.75 m, the table centred on x = 0. The arms are
those of ``TabletopConfig.two_arms()``: ``left/`` at (-0.45, 0) facing +x, ``right/`` at (+0.45, 0)
facing -x (their tool sites rest at x = -/+0.143 m, 0.49 m above the table at home). The cube rests
on a fixed square post (the **stand**, ``STAND_HALF``) at the origin of the table, so its faces are
free on all four sides for the grippers. One RGB camera ``front`` looks at the cube from -y, slightly
above, with both hands in view.

The scramble is an ``CubeInstance``: a normalised lattice state (DBL home) and, for the public set,
the quarter turns that produce it. The cube is built already scrambled (``CubeConfig.orient``), so the
scramble is the model's default state as well as its keyframe ``initial``.

Scrambles: with a secret, a state drawn uniformly from the 3,674,160 states of the 2x2x2 (rejecting the
few closer than ``MIN_DEPTH`` quarter turns to solved: 688 of them, 0.02 %); without one, the first of
``PUBLIC_SCRAMBLES`` (published, for development).
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from rle_design.scene.camera import look_at_quat
from rle_design.scene.tabletop import STIFF_SOLREF, TabletopConfig, build_tabletop, finish
from rle_tasks.core.runtime.secrets import Secret, derive_rng
from rle_tasks.f03_physical_reasoning.constants import CUBE_ID
from rle_tasks.f03_physical_reasoning.cube.coords import N_STATES, decode
from rle_tasks.f03_physical_reasoning.cube.distance import optimal_turns
from rle_tasks.f03_physical_reasoning.cube.lattice import SOLVED, LatticeState
from rle_tasks.f03_physical_reasoning.cube.model import CubeConfig

__all__ = [
    "CUBE_NAME",
    "MIN_DEPTH",
    "PUBLIC_SCRAMBLES",
    "STAND_HALF",
    "STAND_TOP_Z",
    "TABLE",
    "CubeInstance",
    "cube_config",
    "instance",
    "scene_xml",
]

TABLE = TabletopConfig.two_arms(cameras=("east", "south", "above"), look_at=(0.0, 0.0, 0.85))
"""The two-arm table; its three wide cameras are renamed so the cube camera can be ``front``."""
CUBE_NAME = "cube"
STAND_HALF = (0.015, 0.015, 0.03)
"""Half extents of the stand, a 30 mm square post 60 mm tall [m]: narrower than the cube's 64 mm, so
fingers closing on any side face clear it."""
STAND_TOP_Z = TABLE.top_z + 2 * STAND_HALF[2]
"""Height of the stand's top, on which the cube rests [m]."""
CUBE_CENTRE = (0.0, 0.0, STAND_TOP_Z + 0.032 + 0.0005)
"""Centre of the resting cube (0.5 mm above contact, it settles in a few steps) [m]."""
CAMERA_POS = (0.0, -0.5, 1.05)
"""Front camera position [m]: 0.54 m from the cube, so at 320 px and 50 deg the cube spans ~40 px."""
MIN_DEPTH = 4
"""Fewest quarter turns from solved of any scramble (the issue: depth >= 4)."""
PUBLIC_SCRAMBLES: tuple[str, ...] = (
    "R U R' U'",
    "U R U R'",
    "R U F' U'",
    "F R' U R F'",
    "U R U' F R'",
    "R F U R' F' U",
)
"""Published development scrambles (quarter turns in the DBL frame, see ``cube/README.md``); each is
``MIN_DEPTH`` or more quarter turns from solved (tested)."""


@dataclass(frozen=True)
class CubeInstance:
    """The scramble of one attempt.

    Attributes:
        state: Normalised lattice state the cube starts in.
        moves: The public scramble's quarter turns ("" for a drawn scramble).
    """

    state: LatticeState
    moves: str = ""

    @classmethod
    def from_moves(cls, moves: str) -> CubeInstance:
        return cls(SOLVED.apply_all(moves.split()).normalized(), moves)

    @classmethod
    def draw(cls, rng: np.random.Generator) -> CubeInstance:
        """A uniform random state at least ``MIN_DEPTH`` quarter turns from solved."""
        while True:
            state = decode(int(rng.integers(N_STATES)))
            if optimal_turns(state) >= MIN_DEPTH:
                return cls(state)

    @property
    def optimal(self) -> int:
        """Fewest quarter turns that solve the scramble (distance table)."""
        return optimal_turns(self.state)


def instance(secret: Secret) -> CubeInstance:
    """The scramble of a secret: the first public scramble without a secret, else drawn from it."""
    if secret.public:
        return CubeInstance.from_moves(PUBLIC_SCRAMBLES[0])
    return CubeInstance.draw(derive_rng(secret, CUBE_ID, "scramble"))


def cube_config(inst: CubeInstance) -> CubeConfig:
    """The cube of an instance, resting on the stand."""
    return CubeConfig(name=CUBE_NAME, pos=CUBE_CENTRE, orient=inst.state.orient)


def scene_spec(inst: CubeInstance, n_userdata: int = 0) -> mujoco.MjSpec:
    """Table, two arms, stand, scrambled cube, front camera; keyframe ``initial``."""
    spec = build_tabletop(TABLE)
    world = spec.worldbody
    world.add_geom(
        name="stand",
        type=mujoco.mjtGeom.mjGEOM_BOX,
        size=list(STAND_HALF),
        pos=[0.0, 0.0, TABLE.top_z + STAND_HALF[2]],
        friction=[1.0, 0.005, 0.0001],
        condim=3,
        solref=list(STIFF_SOLREF),
        rgba=[0.35, 0.35, 0.38, 1.0],
    )
    look = np.array(CUBE_CENTRE)
    world.add_camera(
        name="front",
        pos=list(CAMERA_POS),
        quat=list(look_at_quat(np.array(CAMERA_POS), look, (0.0, 0.0, 1.0))),
        fovy=50.0,
    )
    cube_config(inst).edit_spec(spec)
    spec.nuserdata = n_userdata
    return finish(spec, TABLE)


def scene_xml(inst: CubeInstance, n_userdata: int = 0) -> str:
    """MJCF of ``scene_spec``."""
    return scene_spec(inst, n_userdata).to_xml()
