"""Seeded physical variations: what a hidden evaluation perturbs, drawn from declared ranges.

A ``VariationSpace`` declares perturbation terms (friction scale, mass scale, centre-of-mass
offset, point mass, ...), each with its range and unit. ``space.sample(rng)`` draws every term in
declaration order from a ``numpy.random.Generator`` (one ``rng.uniform`` call per term, ``size``
values for a term with several), so a draw is reproducible from the generator's seed alone. The
resulting ``Variation`` edits a spec before compiling (``edit_spec``) or returns an edited copy of a
compiled model (``apply``); ``space.nominal()`` is the unperturbed variation.
"""

from __future__ import annotations

import abc
import copy
import math
from collections.abc import Iterator
from dataclasses import dataclass

import mujoco
import numpy as np

from rle_design.errors import ConfigError, MissingElement
from rle_design.scene.elements import element_id

__all__ = [
    "ComOffset",
    "FrictionScale",
    "MassScale",
    "Perturbation",
    "PointMass",
    "Uniform",
    "Variation",
    "VariationSpace",
]


@dataclass(frozen=True)
class Uniform:
    """A uniform range ``[low, high]`` with its unit."""

    low: float
    """Lower bound [unit]."""
    high: float
    """Upper bound [unit]."""
    unit: str
    """Unit of the bounds, e.g. ``"1"`` for a factor, ``"m"``, ``"kg"``."""

    def validate(self, where: str) -> None:
        if not (math.isfinite(self.low) and math.isfinite(self.high)) or self.low > self.high:
            raise ConfigError(
                f"{where}: range must be finite with low <= high, got [{self.low}, {self.high}]"
            )

    def draw(self, rng: np.random.Generator, size: int) -> tuple[float, ...]:
        """``size`` values from one ``rng.uniform`` call (a scalar call when ``size`` is 1)."""
        if size == 1:
            return (float(rng.uniform(self.low, self.high)),)
        return tuple(float(v) for v in rng.uniform(self.low, self.high, size))


class Perturbation(abc.ABC):
    """One perturbed quantity: a range, how many values to draw, and how to apply them."""

    name: str
    range: Uniform
    neutral: float  # value that leaves the model unchanged

    @property
    def size(self) -> int:
        """Number of values drawn."""
        return 1

    def validate(self) -> None:
        if not self.name:
            raise ConfigError(f"{type(self).__name__}.name must not be empty")
        self.range.validate(f"{type(self).__name__} '{self.name}'")

    @abc.abstractmethod
    def edit_spec(self, spec: mujoco.MjSpec, values: tuple[float, ...]) -> None:
        """Apply ``values`` to a spec before compiling."""

    @abc.abstractmethod
    def apply(self, model: mujoco.MjModel, values: tuple[float, ...]) -> None:
        """Apply ``values`` to a compiled model in place."""


def _spec_item(spec: mujoco.MjSpec, kind: str, name: str):
    item = getattr(spec, kind)(name)
    if item is None:
        names = [e.name for e in getattr(spec, f"{kind}s") if e.name]
        raise MissingElement(kind, name, available=names)
    return item


@dataclass(frozen=True)
class FrictionScale(Perturbation):
    """One factor on a friction coefficient of named geoms and contact pairs."""

    name: str
    """Key of the drawn value in the ``Variation``."""
    range: Uniform
    """Range of the factor [1]."""
    geoms: tuple[str, ...] = ()
    """Geoms whose ``friction[axis]`` is scaled."""
    pairs: tuple[str, ...] = ()
    """Contact pairs whose ``friction[axis]`` is scaled (pairs have five coefficients)."""
    axis: int = 0
    """Friction coefficient index: geoms 0 sliding, 1 torsional, 2 rolling; pairs 0-1 sliding."""
    neutral: float = 1.0

    def validate(self) -> None:
        super().validate()
        if not (self.geoms or self.pairs):
            raise ConfigError(f"FrictionScale '{self.name}' names no geom and no pair")
        if self.range.low <= 0:
            raise ConfigError(f"FrictionScale '{self.name}': factors must be > 0, got low {self.range.low}")
        if not 0 <= self.axis < (3 if self.geoms else 5):
            raise ConfigError(f"FrictionScale '{self.name}': axis {self.axis} out of range")

    def edit_spec(self, spec: mujoco.MjSpec, values: tuple[float, ...]) -> None:
        for kind, names in (("geom", self.geoms), ("pair", self.pairs)):
            for n in names:
                item = _spec_item(spec, kind, n)
                friction = np.array(item.friction, dtype=float)
                friction[self.axis] *= values[0]
                item.friction = friction

    def apply(self, model: mujoco.MjModel, values: tuple[float, ...]) -> None:
        for n in self.geoms:
            model.geom_friction[element_id(model, "geom", n), self.axis] *= values[0]
        for n in self.pairs:
            model.pair_friction[element_id(model, "pair", n), self.axis] *= values[0]


@dataclass(frozen=True)
class MassScale(Perturbation):
    """Factors on the mass and rotational inertia of named bodies (centre of mass unchanged)."""

    name: str
    """Key of the drawn values in the ``Variation``."""
    range: Uniform
    """Range of the factors [1]."""
    bodies: tuple[str, ...]
    """Scaled bodies; they need an explicit ``<inertial>`` for ``edit_spec``."""
    per_body: bool = True
    """One factor per body (drawn in ``bodies`` order) or one shared factor."""
    neutral: float = 1.0

    @property
    def size(self) -> int:
        return len(self.bodies) if self.per_body else 1

    def validate(self) -> None:
        super().validate()
        if not self.bodies:
            raise ConfigError(f"MassScale '{self.name}' names no body")
        if self.range.low <= 0:
            raise ConfigError(f"MassScale '{self.name}': factors must be > 0, got low {self.range.low}")

    def _factors(self, values: tuple[float, ...]) -> tuple[float, ...]:
        return values if self.per_body else values * len(self.bodies)

    def edit_spec(self, spec: mujoco.MjSpec, values: tuple[float, ...]) -> None:
        for n, f in zip(self.bodies, self._factors(values)):
            body = _spec_item(spec, "body", n)
            if not body.explicitinertial:
                raise ConfigError(
                    f"MassScale '{self.name}': body '{n}' has no explicit <inertial>; scale it on the "
                    "compiled model with Variation.apply",
                    code="scene.implicit_inertia",
                )
            body.mass = body.mass * f
            body.inertia = np.asarray(body.inertia) * f
            full = np.asarray(body.fullinertia, dtype=float)
            if np.all(np.isfinite(full)):
                body.fullinertia = full * f

    def apply(self, model: mujoco.MjModel, values: tuple[float, ...]) -> None:
        for n, f in zip(self.bodies, self._factors(values)):
            b = element_id(model, "body", n)
            model.body_mass[b] *= f
            model.body_inertia[b] *= f


@dataclass(frozen=True)
class ComOffset(Perturbation):
    """An offset of a body's centre of mass, each axis drawn from the same range."""

    name: str
    """Key of the drawn offset in the ``Variation``."""
    range: Uniform
    """Range of each component [m]."""
    body: str
    """Body whose centre of mass moves (offset in its inertial frame's parent, the body frame)."""
    neutral: float = 0.0

    @property
    def size(self) -> int:
        return 3

    def edit_spec(self, spec: mujoco.MjSpec, values: tuple[float, ...]) -> None:
        body = _spec_item(spec, "body", self.body)
        body.ipos = np.asarray(body.ipos) + np.asarray(values)

    def apply(self, model: mujoco.MjModel, values: tuple[float, ...]) -> None:
        model.body_ipos[element_id(model, "body", self.body)] += np.asarray(values)


@dataclass(frozen=True)
class PointMass(Perturbation):
    """A point mass at a site, rigidly added to the site's body (a payload, a sensor, a screw)."""

    name: str
    """Key of the drawn mass in the ``Variation``."""
    range: Uniform
    """Range of the mass [kg]."""
    site: str
    """Site where the mass sits."""
    neutral: float = 0.0

    def validate(self) -> None:
        super().validate()
        if self.range.low < 0:
            raise ConfigError(f"PointMass '{self.name}': masses must be >= 0, got low {self.range.low}")

    def edit_spec(self, spec: mujoco.MjSpec, values: tuple[float, ...]) -> None:
        if values[0] <= 0:
            return
        site = _spec_item(spec, "site", self.site)
        parent = site.parent
        body = parent.add_body(name=f"{self.name}_point_mass", pos=site.pos, quat=site.quat)
        body.explicitinertial = True
        body.ipos = [0.0, 0.0, 0.0]
        body.iquat = [1.0, 0.0, 0.0, 0.0]
        body.mass = values[0]
        body.inertia = [1e-9, 1e-9, 1e-9]  # a point; MuJoCo wants a positive inertia

    def apply(self, model: mujoco.MjModel, values: tuple[float, ...]) -> None:
        if values[0] <= 0:
            return
        sid = element_id(model, "site", self.site)
        _merge_point_mass(model, int(model.site_bodyid[sid]), model.site_pos[sid].copy(), values[0])


def _merge_point_mass(model: mujoco.MjModel, b: int, p: np.ndarray, mp: float) -> None:
    """Add mass ``mp`` [kg] at ``p`` (body frame) to body ``b``: new COM, parallel-axis inertia."""
    m0, c0 = float(model.body_mass[b]), model.body_ipos[b].copy()
    rot = np.zeros(9)
    mujoco.mju_quat2Mat(rot, model.body_iquat[b])
    rot = rot.reshape(3, 3)
    i_body = rot @ np.diag(model.body_inertia[b]) @ rot.T
    c = (m0 * c0 + mp * p) / (m0 + mp)
    i_new = np.zeros((3, 3))
    for mass, pt, ii in ((m0, c0, i_body), (mp, p, np.zeros((3, 3)))):
        d = pt - c
        i_new += ii + mass * (d @ d * np.eye(3) - np.outer(d, d))
    w, v = np.linalg.eigh(i_new)
    if np.linalg.det(v) < 0:
        v[:, 0] *= -1
    q = np.zeros(4)
    mujoco.mju_mat2Quat(q, v.reshape(-1))
    model.body_mass[b] = m0 + mp
    model.body_ipos[b] = c
    model.body_inertia[b] = w
    model.body_iquat[b] = q


@dataclass(frozen=True)
class Variation:
    """One draw of a ``VariationSpace``: a value tuple per term, in declaration order."""

    terms: tuple[Perturbation, ...]
    """The perturbations."""
    values: tuple[tuple[float, ...], ...]
    """Drawn values of each term [the term's unit]."""

    def __getitem__(self, name: str) -> tuple[float, ...]:
        for term, vals in zip(self.terms, self.values):
            if term.name == name:
                return vals
        raise KeyError(f"variation term '{name}' does not exist. Available: {', '.join(self.names)}")

    @property
    def names(self) -> list[str]:
        return [t.name for t in self.terms]

    def __iter__(self) -> Iterator[tuple[Perturbation, tuple[float, ...]]]:
        return iter(zip(self.terms, self.values))

    def select(self, *names: str) -> Variation:
        """The same draw restricted to some terms (e.g. a scene without the body a term perturbs).

        Raises:
            KeyError: A name is not a term; lists the terms.
        """
        for n in names:
            self[n]
        keep = [i for i, t in enumerate(self.terms) if t.name in names]
        return Variation(tuple(self.terms[i] for i in keep), tuple(self.values[i] for i in keep))

    def edit_spec(self, spec: mujoco.MjSpec) -> None:
        """Apply every term to ``spec`` (before compiling), in declaration order."""
        for term, vals in self:
            term.edit_spec(spec, vals)

    def apply(self, model: mujoco.MjModel) -> mujoco.MjModel:
        """Copy of ``model`` with every term applied in order, then ``mj_setConst`` (derived constants)."""
        out = copy.deepcopy(model)
        for term, vals in self:
            term.apply(out, vals)
        mujoco.mj_setConst(out, mujoco.MjData(out))
        return out


@dataclass(frozen=True)
class VariationSpace:
    """Declared perturbations; ``sample`` draws a ``Variation``."""

    terms: tuple[Perturbation, ...]
    """Perturbations, drawn in this order."""

    def validate(self) -> None:
        for t in self.terms:
            t.validate()
        names = [t.name for t in self.terms]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise ConfigError(f"VariationSpace: term names must be unique, repeated: {', '.join(dup)}")

    def sample(self, rng: np.random.Generator) -> Variation:
        """Draw every term in order from ``rng`` (reproducible from its seed)."""
        self.validate()
        return Variation(self.terms, tuple(t.range.draw(rng, t.size) for t in self.terms))

    def nominal(self) -> Variation:
        """The variation that leaves the model unchanged (factors 1, offsets and masses 0)."""
        self.validate()
        return Variation(self.terms, tuple((t.neutral,) * t.size for t in self.terms))
