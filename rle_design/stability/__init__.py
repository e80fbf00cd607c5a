"""Stability toolkit: support polygon, static margin, force-angle measure, contact forces and batteries."""

from rle_design.rollout import root_tilt
from rle_design.stability.battery import (
    Scenario,
    ScenarioResult,
    StabilityProbe,
    run_battery,
    run_scenario,
    tip_acceleration,
)
from rle_design.stability.contacts import ContactSample, SupportSet, centre_of_pressure, sample_contacts
from rle_design.stability.force_angle import ForceAngle, force_angle
from rle_design.stability.support_loss import SupportLossMonitor
from rle_design.stability.support_polygon import (
    StabilityError,
    SupportPolygon,
    convex_hull,
    static_margin,
    support_polygon,
)
from rle_design.stability.terms import SupportLoad, SupportLost

__all__ = [
    "ContactSample",
    "ForceAngle",
    "Scenario",
    "ScenarioResult",
    "StabilityError",
    "StabilityProbe",
    "SupportLoad",
    "SupportLossMonitor",
    "SupportLost",
    "SupportPolygon",
    "SupportSet",
    "centre_of_pressure",
    "convex_hull",
    "force_angle",
    "root_tilt",
    "run_battery",
    "run_scenario",
    "sample_contacts",
    "static_margin",
    "support_polygon",
    "tip_acceleration",
]
