"""Goal predicates of the composite kitchen tasks, over roles: each names the objects, fixtures and
burners by role, says itself in words for the instruction (``words``) and becomes a ``Condition`` of
the scene once the roles are bound (``condition``); a composite task's success is their conjunction
(``composition.CompositeTask``)."""

from __future__ import annotations

from dataclasses import dataclass

from rle_tasks.envs.kitchen import predicates as pr
from rle_tasks.envs.kitchen.fixture import Fixture
from rle_tasks.envs.kitchen.tasks import FLAT_KINDS, Condition, Episode

__all__ = [
    "BurnerOff",
    "BurnerOn",
    "GripperFar",
    "InReceptacle",
    "Inside",
    "IsClosed",
    "IsOpen",
    "NotInReceptacle",
    "NotInside",
    "OnBurner",
    "OnCounter",
]


@dataclass(frozen=True)
class Roles:
    """A composite episode's roles bound: fixtures by name, role -> name, object name -> category."""

    fixtures: dict[str, Fixture]
    bind: dict[str, str]
    objects: dict[str, str]
    names: object

    def fx(self, role: str) -> Fixture:
        return self.fixtures[self.bind[role]]


@dataclass(frozen=True)
class Inside:
    obj: str
    fixture: str

    def words(self, ep: Episode) -> str:
        return f"{_cat(ep, self.obj)} inside the {_fix_word(ep, self.fixture)}"

    def condition(self, c: Roles) -> Condition:
        f, name, cat = c.fx(self.fixture), c.bind[self.obj], c.objects[self.obj]
        return Condition("", lambda m, d: pr.inside(m, d, name, cat, f.interior))


@dataclass(frozen=True)
class NotInside(Inside):
    def words(self, ep: Episode) -> str:
        return f"{_cat(ep, self.obj)} out of the {_fix_word(ep, self.fixture)}"

    def condition(self, c: Roles) -> Condition:
        inner = super().condition(c).fn
        return Condition("", lambda m, d: not inner(m, d))


@dataclass(frozen=True)
class InReceptacle:
    obj: str
    container: str

    def words(self, ep: Episode) -> str:
        return f"{_cat(ep, self.obj)} in the {_cat(ep, self.container)}"

    def condition(self, c: Roles) -> Condition:
        o, r, cat = c.bind[self.obj], c.bind[self.container], c.objects[self.container]
        return Condition("", lambda m, d: pr.in_receptacle(m, d, o, r, cat))


@dataclass(frozen=True)
class NotInReceptacle(InReceptacle):
    def words(self, ep: Episode) -> str:
        return f"{_cat(ep, self.obj)} out of the {_cat(ep, self.container)}"

    def condition(self, c: Roles) -> Condition:
        o, r, cat = c.bind[self.obj], c.bind[self.container], c.objects[self.container]
        return Condition("", lambda m, d: not pr.in_receptacle(m, d, o, r, cat))


@dataclass(frozen=True)
class IsOpen:
    fixture: str

    def words(self, ep: Episode) -> str:
        return f"{_fix_word(ep, self.fixture)} open"

    def condition(self, c: Roles) -> Condition:
        f = c.fx(self.fixture)
        return Condition("", lambda m, d: pr.is_open(m, d, f))


@dataclass(frozen=True)
class IsClosed:
    fixture: str

    def words(self, ep: Episode) -> str:
        return f"{_fix_word(ep, self.fixture)} closed"

    def condition(self, c: Roles) -> Condition:
        f = c.fx(self.fixture)
        return Condition("", lambda m, d: pr.is_closed(m, d, f))


@dataclass(frozen=True)
class BurnerOn:
    burner: str

    def words(self, ep: Episode) -> str:
        return f"{ep.target[self.burner].replace('_', ' ')} burner on"

    def condition(self, c: Roles) -> Condition:
        knob = c.fixtures[c.bind["stove"]].burners[c.bind[self.burner]][0]
        return Condition("", lambda m, d: pr.knob_on(m, d, knob))


@dataclass(frozen=True)
class BurnerOff(BurnerOn):
    def words(self, ep: Episode) -> str:
        return f"{ep.target[self.burner].replace('_', ' ')} burner off"

    def condition(self, c: Roles) -> Condition:
        on = super().condition(c).fn
        return Condition("", lambda m, d: not on(m, d))


@dataclass(frozen=True)
class OnCounter:
    obj: str

    def words(self, ep: Episode) -> str:
        return f"{_cat(ep, self.obj)} on a counter"

    def condition(self, c: Roles) -> Condition:
        o = c.bind[self.obj]
        tops = tuple(g for f in c.fixtures.values() if f.kind in FLAT_KINDS for g in f.top_geoms)
        return Condition("", lambda m, d: pr.bodies_touch(m, d, o, {m.geom(g).id for g in tops}))


@dataclass(frozen=True)
class OnBurner:
    obj: str
    burner: str

    def words(self, ep: Episode) -> str:
        return f"{_cat(ep, self.obj)} on the {ep.target[self.burner].replace('_', ' ')} burner"

    def condition(self, c: Roles) -> Condition:
        o, stove, burner = c.bind[self.obj], c.fixtures[c.bind["stove"]], c.bind[self.burner]
        site = stove.sites[f"{burner}_burner"]
        cook = stove.top_geoms[0]
        return Condition("", lambda m, d: pr.on_site(m, d, o, cook, site, 0.09))


@dataclass(frozen=True)
class GripperFar:
    obj: str

    def words(self, ep: Episode) -> str:
        return f"gripper away from the {_cat(ep, self.obj)}"

    def condition(self, c: Roles) -> Condition:
        o, names = c.bind[self.obj], c.names
        return Condition("", lambda m, d: pr.gripper_far(m, d, o, names.finger_pads))


Predicate = (
    Inside
    | NotInside
    | InReceptacle
    | NotInReceptacle
    | IsOpen
    | IsClosed
    | BurnerOn
    | BurnerOff
    | OnCounter
    | OnBurner
    | GripperFar
)
FIXTURE_WORDS = {
    "drawer_cabinet": "drawer",
    "hinge_cabinet": "cabinet",
    "dish_rack": "dish rack",
    "wall_cabinet": "wall cabinet",
}


def _cat(ep: Episode, role: str) -> str:
    for p in ep.objects:
        if p.name == ep.target.get(role, role):
            return p.category
    return role


def _fix_word(ep: Episode, role: str) -> str:
    kind = ep.target.get(f"{role}.kind", role)
    return FIXTURE_WORDS.get(kind, kind)
