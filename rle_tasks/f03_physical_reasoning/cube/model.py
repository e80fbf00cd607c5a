"""MjSpec builder of the physical 64 mm pocket cube: a core, eight cubies on ball joints, stickers.

Mechanism (one concept: a layer turns only as a whole and settles on the lattice):

1. The core is the cube's root body (free joint, or fixed to its parent for bench tests). Each cubie is
   a 31.6 mm box hanging from the core's centre on a ball joint, so it can only rotate about that
   centre: its slot follows from its orientation.
2. Neighbouring cubies collide (box-box, frictionless ``condim=1`` so layers slide on each other). A box
   whose inner corner sits at the rotation centre cannot rotate at all unless its neighbours rotate
   with it; the only free motions of the assembly are the six layer turns (and a turn of all eight
   cubies together relative to the core, which changes nothing visible).
3. A detent (``detent.CubeDetent``, applied by the stepping loop before every ``mj_step``) acts between
   touching cubies: soft along a layer turn (it snaps the layer to the nearest quarter turn), stiff and
   damped against any tilt. Its gains are stored in the model as the numeric ``<name>_detent``.

Contacts with other bodies (grippers, table) use the partner geom's ``condim`` (MuJoCo takes the
larger), so partners need ``condim >= 3`` to grip. Stickers are visual only (no contact, no mass).
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from rle_design.errors import ConfigError
from rle_design.scene.config import SpecEdit, check_positive, check_vector
from rle_tasks.f03_physical_reasoning.cube.group import IDENTITY, QUATS, ROTATIONS
from rle_tasks.f03_physical_reasoning.cube.lattice import COLOURS, CUBIES, FACE_NORMALS, SLOTS, LatticeState

__all__ = ["CubeConfig", "cube_spec"]


@dataclass(frozen=True)
class CubeConfig(SpecEdit):
    """A pocket cube added to the world body of a spec."""

    name: str = "cube"
    """Name of the core body; cubies are ``<name>_<CUBIE>`` (e.g. ``cube_UFR``)."""
    pos: tuple[float, float, float] = (0.0, 0.0, 0.032)
    """Initial position of the cube's centre in the world [m]."""
    edge: float = 0.064
    """Edge length of the whole cube [m]."""
    gap: float = 0.0004
    """Clearance between neighbouring cubies [m]."""
    cubie_mass: float = 0.0075
    """Mass of one cubie with its stickers [kg] (8 x 7.5 g + 4 g core = 64 g, a typical 2x2x2)."""
    core_mass: float = 0.004
    """Mass of the core [kg]."""
    friction: tuple[float, float, float] = (1.0, 0.005, 0.0001)
    """Sliding [1], torsional [m], rolling [m] friction of the cubie surfaces against other bodies."""
    detent_stiffness: float = 4e-3
    """Turn detent of one straddling cubie pair [N m/rad] (a layer has four: 16 mN m/rad)."""
    tilt_stiffness: float = 0.1
    """Stiffness of a cubie pair against relative tilt (any rotation but a turn) [N m/rad]."""
    tilt_damping: float = 0.0
    """Damping of a cubie pair's relative tilt [N m s/rad]."""
    damping: float = 3e-4
    """Ball-joint damping of each cubie [N m s/rad] (about critical for the detent and cubie inertia)."""
    free: bool = True
    """True: the core has a free joint; False: the core is fixed (mechanism tests)."""
    orient: tuple[int, ...] = ()
    """Initial lattice orientation of each cubie relative to the core (``group.ROTATIONS`` indices,
    ``CUBIES`` order; a ``LatticeState.orient``); empty: solved. Each cubie body is built already turned
    (its ball joint's zero is that orientation), so a scrambled cube is the model's default state."""

    def validate(self) -> None:
        if not self.name:
            raise ConfigError("CubeConfig.name must not be empty")
        check_vector(self, "pos", self.pos, 3)
        for field in ("edge", "cubie_mass", "core_mass", "detent_stiffness", "tilt_stiffness"):
            check_positive(self, field, getattr(self, field))
        check_positive(self, "gap", self.gap, strict=False)
        check_positive(self, "damping", self.damping, strict=False)
        check_positive(self, "tilt_damping", self.tilt_damping, strict=False)
        if self.gap >= self.edge / 4:
            raise ConfigError(f"CubeConfig.gap must be < edge/4 = {self.edge / 4}, got {self.gap}")
        check_vector(self, "friction", self.friction, 3)
        if self.orient:
            try:
                valid = LatticeState(tuple(self.orient)).is_valid()
            except ValueError as exc:
                raise ConfigError(f"CubeConfig.orient: {exc}") from None
            if not valid:
                raise ConfigError(f"CubeConfig.orient puts two cubies in one slot: {self.orient}")

    @property
    def cubie_half(self) -> float:
        """Half edge of one cubie box [m]."""
        return (self.edge / 2 - self.gap) / 2

    def cubie_body(self, cubie: str) -> str:
        """Body name of a cubie (``CUBIES``)."""
        return self.name + "_" + cubie

    def _edit(self, spec: mujoco.MjSpec) -> None:
        core = spec.worldbody.add_body(name=self.name, pos=list(self.pos))
        if self.free:
            core.add_freejoint(name=self.name + "_free")
        core.add_geom(
            name=self.name + "_core",
            type=mujoco.mjtGeom.mjGEOM_SPHERE,
            size=[self.edge / 8, 0, 0],
            mass=self.core_mass,
            contype=0,
            conaffinity=0,
            group=3,
            rgba=[0.2, 0.2, 0.2, 1.0],
        )
        spec.add_numeric(
            name=self.name + "_detent", data=[self.detent_stiffness, self.tilt_stiffness, self.tilt_damping]
        )
        offset = self.edge / 4
        half = self.cubie_half
        orient = self.orient or (IDENTITY,) * len(CUBIES)
        for cubie, slot, rot in zip(CUBIES, SLOTS, orient):
            centre = [float(s) * offset for s in slot]
            cb = core.add_body(
                name=self.cubie_body(cubie),
                pos=(ROTATIONS[rot] @ np.asarray(centre)).tolist(),
                quat=QUATS[rot].tolist(),
            )
            cb.add_joint(
                name=self.cubie_body(cubie) + "_ball",
                type=mujoco.mjtJoint.mjJNT_BALL,
                pos=[-c for c in centre],
                damping=self.damping,
            )
            cb.add_geom(
                name=self.cubie_body(cubie) + "_box",
                type=mujoco.mjtGeom.mjGEOM_BOX,
                size=[half, half, half],
                mass=self.cubie_mass,
                friction=list(self.friction),
                condim=1,
                rgba=[0.06, 0.06, 0.06, 1.0],
            )
            for face, normal in FACE_NORMALS.items():
                if int(normal @ slot) <= 0:
                    continue
                thick = 0.0004
                size = [half * 0.86] * 3
                pos = [0.0, 0.0, 0.0]
                for k in range(3):
                    if normal[k]:
                        size[k] = thick / 2
                        pos[k] = float(normal[k]) * (half + thick / 2)
                cb.add_geom(
                    name=self.cubie_body(cubie) + "_" + face,
                    type=mujoco.mjtGeom.mjGEOM_BOX,
                    size=size,
                    pos=pos,
                    mass=0.0,
                    contype=0,
                    conaffinity=0,
                    group=2,
                    rgba=list(COLOURS[face]),
                )


def cube_spec(
    config: CubeConfig | None = None, *, floor: bool = True, timestep: float = 0.002
) -> mujoco.MjSpec:
    """A spec holding only the cube (and a floor plane at z = 0 when ``floor``), for tests and benchmarks."""
    spec = mujoco.MjSpec()
    spec.modelname = "pocket_cube"
    spec.option.timestep = timestep
    if floor:
        spec.worldbody.add_geom(name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[1.0, 1.0, 0.05])
    (config or CubeConfig()).edit_spec(spec)
    return spec
