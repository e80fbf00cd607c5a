"""Composite kitchen tasks as data: roles, an initial-state sampler, and a conjunction of predicates.

A ``CompositeTask`` names **roles** and binds them when an episode is sampled:

- fixture roles (``Fx``): a fixture of one of the given kinds, optionally the one nearest another role;
- object roles (``Obj``): an object of one of the given categories, placed ``On`` a flat counter top next to
  a fixture role, ``In`` a fixture role's interior (drawer tray, cabinet, microwave plate, sink basin,
  dish rack, fridge shelf) or ``Into`` another object role (a container);
- burner roles (``Burner``): one burner of the stove role, on or off at the start;
- initial door and drawer states (``Joint``: fraction of the range), and the fixture the robot faces.

Its success is the conjunction of its predicates (``Inside``, ``NotInside``, ``InReceptacle``,
``NotInReceptacle``, ``IsOpen``, ``IsClosed``, ``BurnerOn``, ``BurnerOff``, ``OnCounter``, ``OnBurner``,
``GripperFar``), each a ``Condition`` of the scene, so the stage report (family 02) evaluates each one.
A composite task is a ``KitchenTask`` (``sample``/``conditions``), so the scene builder, the environment
and the metered sessions serve it as they serve the atomic tasks.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from rle_tasks.envs.kitchen.fixture import BURNERS, Fixture
from rle_tasks.envs.kitchen.goals import FIXTURE_WORDS, Predicate, Roles
from rle_tasks.envs.kitchen.placement import STANDOFF, spawn, spot_near
from rle_tasks.envs.kitchen.tasks import Condition, Episode, KitchenTask, Placement

__all__ = [
    "Burner",
    "CompositeTask",
    "Fx",
    "In",
    "Into",
    "Joint",
    "Obj",
    "On",
]


@dataclass(frozen=True)
class Fx:
    """A fixture role: a fixture of one of ``kinds``, the one nearest to role ``near`` when given."""

    role: str
    kinds: tuple[str, ...]
    near: str | None = None


@dataclass(frozen=True)
class On:
    """On the flat counter top nearest to fixture role ``fixture`` (its own top when it has one)."""

    fixture: str


@dataclass(frozen=True)
class In:
    """Inside fixture role ``fixture``'s interior, on its floor."""

    fixture: str


@dataclass(frozen=True)
class Into:
    """Resting in (on) container object role ``container``."""

    container: str


@dataclass(frozen=True)
class Obj:
    """An object role of one of ``categories`` placed at ``at``."""

    role: str
    categories: tuple[str, ...]
    at: On | In | Into


@dataclass(frozen=True)
class Burner:
    """A burner role of the stove role ``stove``, on or off at the start."""

    role: str
    stove: str = "stove"
    on: bool = False
    other_than: str | None = None


@dataclass(frozen=True)
class Joint:
    """Initial state of fixture role ``fixture``'s doors or drawer, a fraction of the range."""

    fixture: str
    fraction: float


@dataclass(frozen=True)
class CompositeTask(KitchenTask):
    """A composite task (see the module docstring).

    Attributes:
        name: Task name.
        instruction: Template; ``{role}`` becomes the role's category (objects) or words (fixtures,
            burners).
        fixtures: Fixture roles, sampled in order (a ``near`` role must come earlier).
        objects: Object roles, placed in order (a container before what goes into it).
        conjuncts: The predicates whose conjunction is success.
        joints: Initial door and drawer states.
        burners: Burner roles.
        focus: Fixture role the robot faces at the start; ``between`` a second role it stands between.
        between: See ``focus``.
    """

    name: str = ""
    instruction: str = ""
    fixtures: tuple[Fx, ...] = ()
    objects: tuple[Obj, ...] = ()
    conjuncts: tuple[Predicate, ...] = ()
    joints: tuple[Joint, ...] = ()
    burners: tuple[Burner, ...] = ()
    focus: str = ""
    between: str | None = None
    description: str = field(default="", compare=False)

    def _bind_fixtures(self, fixtures: dict[str, Fixture], rng: np.random.Generator) -> dict[str, str]:
        bind: dict[str, str] = {}
        for role in self.fixtures:
            pool = sorted(n for n, f in fixtures.items() if f.kind in role.kinds and n not in bind.values())
            if not pool:
                raise ValueError(
                    f"{self.name}: the kitchen has no free fixture of kinds {role.kinds} for role '{role.role}'"
                )
            if role.near is not None:
                x = fixtures[bind[role.near]].pos[0]
                pool = sorted(pool, key=lambda n: (abs(fixtures[n].pos[0] - x), n))[:1]
            bind[role.role] = pool[int(rng.integers(len(pool)))]
        return bind

    def sample(self, fixtures: dict[str, Fixture], rng: np.random.Generator) -> Episode:
        bind = self._bind_fixtures(fixtures, rng)
        target: dict[str, str] = dict(bind)
        target.update({f"{r.role}.kind": fixtures[bind[r.role]].kind for r in self.fixtures})
        for b in self.burners:
            choices = [x for x in BURNERS if x != target.get(b.other_than or "", "")]
            target[b.role] = choices[int(rng.integers(len(choices)))]
        placements: list[Placement] = []
        cats: dict[str, str] = {}
        for o in self.objects:
            cat = o.categories[int(rng.integers(len(o.categories)))]
            cats[o.role] = cat
            name = o.role
            target[o.role] = name
            if isinstance(o.at, On):
                pos = spot_near(fixtures, fixtures[bind[o.at.fixture]], rng, cat, tuple(placements))
                placements.append(Placement(name, cat, pos, float(rng.uniform(-math.pi, math.pi))))
            elif isinstance(o.at, In):
                f = fixtures[bind[o.at.fixture]]
                u, v = rng.uniform(-0.5, 0.5, size=2)
                placements.append(
                    Placement(
                        name,
                        cat,
                        (float(u), float(v), 0.0),
                        float(rng.uniform(-math.pi, math.pi)),
                        inside=f.name,
                    )
                )
            else:
                host = next(p for p in placements if p.name == o.at.container)
                k = sum(p.on == host.name for p in placements)  # side by side: -0.45 r, +0.45 r, ...
                u = (-0.45, 0.45, 0.0)[k % 3]
                placements.append(
                    Placement(
                        name,
                        cat,
                        (u, float(rng.uniform(-0.1, 0.1)), 0.0),
                        float(rng.uniform(-math.pi, math.pi)),
                        on=host.name,
                    )
                )
        joints = []
        for j in self.joints:
            f = fixtures[bind[j.fixture]]
            joints += [(name, j.fraction) for name in f.joints]
        for b in self.burners:
            if b.on:
                joints.append((fixtures[bind[b.stove]].burners[target[b.role]][0], 0.5 + 0.9 / (2 * math.pi)))
        focus = fixtures[bind[self.focus]]
        dx = 0.0 if self.between is None else 0.5 * (fixtures[bind[self.between]].pos[0] - focus.pos[0])
        robot = spawn(rng, focus, dx=float(np.clip(dx, -0.6, 0.6)), standoff=STANDOFF + 0.1)
        words = {r: cats.get(r) or target[r].replace("_", " ") for r in target if "." not in r}
        words.update(
            {
                r.role: FIXTURE_WORDS.get(fixtures[bind[r.role]].kind, fixtures[bind[r.role]].kind)
                for r in self.fixtures
            }
        )
        ep = Episode(
            self.name, self.instruction.format(**words), robot, tuple(joints), tuple(placements), target
        )
        return ep

    def conditions(self, episode: Episode, fixtures: dict[str, Fixture], names) -> tuple[Condition, ...]:
        bind = {k: v for k, v in episode.target.items() if "." not in k}
        cats = {p.name: p.category for p in episode.objects}
        ctx = Roles(fixtures, bind, {r: cats[bind[r]] for r in bind if bind[r] in cats}, names)
        out = []
        for p in self.conjuncts:
            c = p.condition(ctx)
            out.append(Condition(p.words(episode), c.fn))
        return tuple(out)
