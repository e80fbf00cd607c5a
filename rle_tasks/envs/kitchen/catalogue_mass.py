"""Realistic masses of catalogue instances: each category states the typical mass [kg] of one real
product (``catalogue.yaml``: ``mass``, ``mass_source``), that of its first instance; the other instances
of the category scale it by their collision volume (the same bulk density). Every geom of an instance
gets that density, so the inertia is the collision geometry's scaled to the mass."""

from __future__ import annotations

import functools

import mujoco

from rle_tasks.envs.kitchen.catalogue_data import CATEGORIES, instance
from rle_tasks.envs.kitchen.catalogue_geometry import add_geoms


@functools.cache
def volume(instance_id: str) -> float:
    """Volume of the collision geometry [m^3], as MuJoCo integrates it (overlaps counted twice)."""
    spec = mujoco.MjSpec()
    body = spec.worldbody.add_body(name="probe")
    body.add_freejoint()
    add_geoms(body, spec, "probe", instance(instance_id), visual=False, density=1.0)
    return float(spec.compile().body_subtreemass[1])


def source_mass(instance_id: str) -> float:
    """Mass [kg] the source's own densities give (kept for comparison)."""
    spec = mujoco.MjSpec()
    body = spec.worldbody.add_body(name="probe")
    body.add_freejoint()
    add_geoms(body, spec, "probe", instance(instance_id), visual=False)
    return float(spec.compile().body_subtreemass[1])


@functools.cache
def target_mass(instance_id: str) -> float:
    """The instance's mass [kg]: its category's stated mass times its volume over the first instance's."""
    cat = CATEGORIES[instance(instance_id).category]
    return cat.mass * volume(instance_id) / volume(cat.instances[0])


def density(instance_id: str) -> float:
    """Uniform density [kg/m^3] giving the instance its ``target_mass``."""
    return target_mass(instance_id) / volume(instance_id)
