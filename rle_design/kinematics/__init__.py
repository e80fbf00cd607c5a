"""Pinocchio kinematics: models from MJCF, gravity maps, springs, regressors, probe selection, IK.

Heavy modules are imported on first use of their names (``ik`` lives in its own module).
"""

from __future__ import annotations

from rle_design.kinematics.gravity import GravityMap, gravity_torque, static_torque
from rle_design.kinematics.model import (
    DroppedConstruct,
    KinematicModel,
    model_from_mjcf,
    model_from_mujoco,
    precheck_mjcf,
)
from rle_design.kinematics.probes import greedy_d_optimal, information_logdet
from rle_design.kinematics.regressor import (
    BaseParameters,
    base_parameters,
    fit_base,
    gravity_parameters,
    gravity_regressor,
    stacked_regressor,
)
from rle_design.kinematics.springs import (
    JointSpring,
    TendonSpring,
    counterweight_moment,
    spring_torque,
    springs_from_mujoco,
    tendon_length,
    torsion_spring_residual,
    zero_length_spring_residual,
    zero_length_spring_torque,
)

__all__ = [
    "BaseParameters",
    "DroppedConstruct",
    "GravityMap",
    "JointSpring",
    "KinematicModel",
    "TendonSpring",
    "base_parameters",
    "counterweight_moment",
    "fit_base",
    "gravity_parameters",
    "gravity_regressor",
    "gravity_torque",
    "greedy_d_optimal",
    "information_logdet",
    "model_from_mjcf",
    "model_from_mujoco",
    "precheck_mjcf",
    "spring_torque",
    "springs_from_mujoco",
    "stacked_regressor",
    "static_torque",
    "tendon_length",
    "torsion_spring_residual",
    "zero_length_spring_residual",
    "zero_length_spring_torque",
]
