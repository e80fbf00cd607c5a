"""Physics options owned by a composed scene (attached children's ``<option>`` are overwritten)."""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from rle_design.errors import ConfigError
from rle_design.scene.config import SpecEdit, check_positive, check_vector

__all__ = ["PhysicsOptions"]


@dataclass(frozen=True)
class PhysicsOptions(SpecEdit):
    """Physics options imposed on a scene, so every attached robot is simulated alike."""

    timestep: float = 0.002
    """Integration step [s]."""
    integrator: int = int(mujoco.mjtIntegrator.mjINT_IMPLICITFAST)
    """MuJoCo integrator, an ``mjtIntegrator`` value."""
    cone: int = int(mujoco.mjtCone.mjCONE_ELLIPTIC)
    """Friction cone, an ``mjtCone`` value; elliptic avoids the creep of pyramidal cones under sustained
    lateral load."""
    noslip_iterations: int = 5
    """Post-solve no-slip iterations (remove soft-contact and frictionloss creep); 0 disables [1]."""
    gravity: tuple[float, float, float] = (0.0, 0.0, -9.81)
    """Gravity vector [m/s^2]."""

    def validate(self) -> None:
        check_positive(self, "timestep", self.timestep)
        integrators = {int(i): i.name for i in mujoco.mjtIntegrator.__members__.values()}
        if int(self.integrator) not in integrators:
            raise ConfigError(
                f"PhysicsOptions.integrator must be an mjtIntegrator value, got {self.integrator}. "
                f"Available: {', '.join(f'{v} ({k})' for v, k in sorted(integrators.items()))}"
            )
        cones = {int(c): c.name for c in mujoco.mjtCone.__members__.values()}
        if int(self.cone) not in cones:
            raise ConfigError(
                f"PhysicsOptions.cone must be an mjtCone value, got {self.cone}. "
                f"Available: {', '.join(f'{v} ({k})' for v, k in sorted(cones.items()))}"
            )
        if self.noslip_iterations < 0:
            raise ConfigError(f"PhysicsOptions.noslip_iterations must be >= 0, got {self.noslip_iterations}")
        check_vector(self, "gravity", self.gravity, 3)

    def _edit(self, spec: mujoco.MjSpec) -> None:
        spec.option.timestep = self.timestep
        spec.option.integrator = self.integrator
        spec.option.cone = self.cone
        spec.option.noslip_iterations = self.noslip_iterations
        spec.option.gravity = np.asarray(self.gravity, dtype=float)
