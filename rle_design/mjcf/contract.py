"""Contract-driven checks of a loaded design: required names and forbidden constructs.

A family states what its artifact must contain and must not do in a ``ModelContract``;
``check_contract`` returns one ``Finding`` per violation, each with a stable code and a message that
names the element and its source line. Forbidden constructs and why a family may forbid them:

- ``gravcomp`` (``contract.gravcomp``): body ``gravcomp`` or joint ``actuatorgravcomp`` cancels
  gravity by fiat; Pinocchio ignores it.
- option changes (``contract.option_changed``): any ``<option>``/``<flag>`` value differing from
  MuJoCo's default, unless listed in ``allowed_options`` (e.g. gravity, timestep, integrator).
- world welds (``contract.world_weld``): an equality ``weld``/``connect`` with the world (``body2``
  omitted, ``world`` named, or a site on the world body) holds a device up for free.
- actuators (``contract.actuator``): any element under ``<actuator>``, e.g. in a passive device.
- multiple roots (``contract.multiple_roots``): more than one body directly under ``<worldbody>``
  (Pinocchio keeps only the first).
- massless bodies (``contract.massless_body``): a body whose compiled mass is below 1e-9 kg.
- frames (``contract.frame``): a body inside ``<frame>`` (Pinocchio drops it).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from rle_design.errors import MissingElement, MjcfError
from rle_design.mjcf.options import option_changes

if TYPE_CHECKING:
    from rle_design.mjcf.loader import Design

__all__ = ["Finding", "ModelContract", "check_contract"]

MASSLESS_KG = 1e-9
_BY_FIAT = "gravity compensation by fiat is forbidden"

_KINDS = {
    "actuator": "actuators",
    "body": "bodies",
    "camera": "cameras",
    "equality": "equalities",
    "geom": "geoms",
    "joint": "joints",
    "sensor": "sensors",
    "site": "sites",
    "tendon": "tendons",
}


@dataclass(frozen=True)
class Finding:
    """One contract or consistency violation.

    Attributes:
        code: Stable code, e.g. ``"contract.gravcomp"``.
        message: Human-readable reason naming the element (and both numbers for mismatches).
        element: Offending element tag, when known.
        line: 1-based source line, when known.
        path: File relative to the artifact directory, when known.
    """

    code: str
    message: str
    element: str | None = None
    line: int | None = None
    path: str | None = None


@dataclass(frozen=True)
class ModelContract:
    """What a design must contain and must not do.

    Attributes:
        required: Kind (``site``, ``body``, ``joint``, ``actuator``, ``geom``, ``sensor``, ``tendon``,
            ``camera``, ``equality``) -> names that must exist.
        forbid_gravcomp: Reject body ``gravcomp`` and joint ``actuatorgravcomp``.
        forbid_option_changes: Reject option values differing from MuJoCo's defaults ...
        allowed_options: ... except these ``MjsOption`` fields or XML attributes (e.g.
            ``("timestep", "integrator")``) and flags named ``"flag.<name>"`` (e.g. ``"flag.contact"``;
            ``"flag"`` allows all flags).
        forbid_world_welds: Reject equality welds/connects involving the world.
        forbid_actuators: Reject any actuator.
        forbid_multiple_roots: Reject more than one body under ``<worldbody>``.
        forbid_massless_bodies: Reject bodies lighter than ``MASSLESS_KG`` (needs a compile).
        forbid_frames: Reject bodies inside ``<frame>``.
        forbid_invalid_inertia: Reject negative or non-finite masses and densities and inertias that
            are not physical (a negative principal moment, or one larger than the sum of the other
            two). MuJoCo accepts some of these silently (it clamps a negative diagonal), so the XML is
            checked. On by default: no contract has a use for them.
    """

    required: Mapping[str, tuple[str, ...]] = field(default_factory=dict)
    forbid_gravcomp: bool = False
    forbid_option_changes: bool = False
    allowed_options: tuple[str, ...] = ()
    forbid_world_welds: bool = False
    forbid_actuators: bool = False
    forbid_multiple_roots: bool = False
    forbid_massless_bodies: bool = False
    forbid_frames: bool = False
    forbid_invalid_inertia: bool = True


def _finding(design: Design, code: str, message: str, el=None) -> Finding:
    if el is None:
        return Finding(code, message.replace("{where}", ""), path=design.entry)
    path, line = design.where(el)
    where = f" (line {line})" if line is not None else ""
    return Finding(code, message.replace("{where}", where), element=str(el.tag), line=line, path=path)


def _name(el, default: str = "unnamed") -> str:
    return el.get("name") or default


def _required(design: Design, contract: ModelContract) -> list[Finding]:
    out = []
    for kind, names in sorted(contract.required.items()):
        if kind not in _KINDS:
            raise MjcfError(f"contract kind '{kind}' does not exist. Available: {', '.join(_KINDS)}")
        available = [e.name for e in getattr(design.spec, _KINDS[kind]) if e.name]
        for name in names:
            if name not in available:
                err = MissingElement(kind, name, available=available)
                out.append(Finding(f"contract.missing_{kind}", err.message, element=kind, path=design.entry))
    return out


def _gravcomp(design: Design) -> list[Finding]:
    out = []
    for el in design.tree.getroot().iter("body", "joint"):
        if el.tag == "body" and float(el.get("gravcomp", "0") or 0) != 0:
            msg = f"body '{_name(el)}'{{where}} sets gravcomp=\"{el.get('gravcomp')}\"; {_BY_FIAT}"
            out.append(_finding(design, "contract.gravcomp", msg, el))
        if el.tag == "joint" and el.get("actuatorgravcomp", "false") == "true":
            msg = f"joint '{_name(el)}'{{where}} sets actuatorgravcomp=\"true\"; {_BY_FIAT}"
            out.append(_finding(design, "contract.gravcomp", msg, el))
    return out


def _options(design: Design, allowed: tuple[str, ...]) -> list[Finding]:
    return [
        _finding(design, "contract.option_changed", msg, el) for msg, el in option_changes(design, allowed)
    ]


def _world_body_sites(design: Design) -> set[str]:
    names = set()
    for wbody in design.tree.getroot().iter("worldbody"):
        for site in wbody.iter("site"):
            parent = site.getparent()
            while parent is not None and parent.tag == "frame":
                parent = parent.getparent()
            if parent is not None and parent.tag == "worldbody" and site.get("name"):
                names.add(site.get("name"))
    return names


def _world_welds(design: Design) -> list[Finding]:
    world_sites = _world_body_sites(design)
    out = []
    for eq in design.tree.getroot().iter("equality"):
        for el in eq:
            if el.tag not in ("weld", "connect"):
                continue
            b1, b2 = el.get("body1"), el.get("body2")
            s1, s2 = el.get("site1"), el.get("site2")
            if s1 or s2:
                hit = [s for s in (s1, s2) if s in world_sites]
                reason = f"site '{hit[0]}' on the world body" if hit else None
            elif b1 == "world" or b2 == "world" or (b1 and not b2):
                other = b1 if b1 != "world" else b2
                reason = f"body '{other}' to the world" + (" (body2 omitted)" if not b2 else "")
            else:
                reason = None
            if reason:
                msg = f"{el.tag} '{_name(el)}'{{where}} ties {reason}; welds/connects to the world are forbidden"
                out.append(_finding(design, "contract.world_weld", msg, el))
    return out


def _actuators(design: Design) -> list[Finding]:
    out = []
    for act in design.tree.getroot().iter("actuator"):
        for el in act:
            if isinstance(el.tag, str):
                msg = f"actuator <{el.tag}> '{_name(el)}'{{where}} is forbidden: the device must be passive"
                out.append(_finding(design, "contract.actuator", msg, el))
    return out


def _root_bodies(design: Design) -> list:
    roots = []
    for wbody in design.tree.getroot().iter("worldbody"):
        stack = list(wbody)
        while stack:
            el = stack.pop(0)
            if el.tag == "body":
                roots.append(el)
            elif el.tag in ("frame", "replicate"):
                stack[:0] = list(el)
    return roots


def _multiple_roots(design: Design) -> list[Finding]:
    roots = _root_bodies(design)
    names = ", ".join(_name(r) for r in roots)
    return [
        _finding(
            design,
            "contract.multiple_roots",
            f"body '{_name(el)}'{{where}} is root body {i + 2} under <worldbody>; exactly one is allowed "
            f"(roots: {names})",
            el,
        )
        for i, el in enumerate(roots[1:])
    ]


def _massless(design: Design) -> list[Finding]:
    try:
        model = design.compile()
    except MjcfError as exc:
        return [Finding(exc.code, exc.message, path=design.entry)]
    out = []
    for i in range(1, model.nbody):
        if model.body_mass[i] < MASSLESS_KG:
            name = model.body(i).name
            el = design.find("body", name) if name else None
            msg = f"body '{name or i}'{{where}} has mass {model.body_mass[i]:.3g} kg; every body needs mass"
            out.append(_finding(design, "contract.massless_body", msg, el))
    return out


def _frames(design: Design) -> list[Finding]:
    out = []
    for frame in design.tree.getroot().iter("frame"):
        for el in frame.iter("body"):
            msg = (
                f"body '{_name(el)}'{{where}} is inside <frame> '{_name(frame)}'; Pinocchio drops such bodies"
            )
            out.append(_finding(design, "contract.frame", msg, el))
    return out


def _numbers(el, attr: str) -> list[float] | None:
    raw = el.get(attr)
    if raw is None:
        return None
    try:
        return [float(v) for v in raw.split()]
    except ValueError:
        return None  # MuJoCo's own schema check reports it


def _principal_moments(el) -> list[float] | None:
    diag = _numbers(el, "diaginertia")
    if diag is not None and len(diag) == 3:
        return diag
    full = _numbers(el, "fullinertia")
    if full is not None and len(full) == 6 and all(math.isfinite(v) for v in full):
        xx, yy, zz, xy, xz, yz = full
        return [float(v) for v in np.linalg.eigvalsh([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])]
    return full


def _invalid_inertia(design: Design) -> list[Finding]:
    out = []
    for el in design.tree.iter("inertial", "geom"):
        owner = el.getparent()
        who = f"<{el.tag}> of body '{_name(owner)}'" if el.tag == "inertial" else f"geom '{_name(el)}'"
        for attr in ("mass", "density"):
            vals = _numbers(el, attr)
            if vals and (not math.isfinite(vals[0]) or vals[0] < 0):
                msg = f"{who}{{where}} has {attr}={el.get(attr)!r}; masses and densities must be finite and >= 0"
                out.append(_finding(design, "contract.invalid_inertia", msg, el))
        if el.tag != "inertial":
            continue
        moments = _principal_moments(el)
        if moments is None:
            continue
        bad = not all(math.isfinite(v) for v in moments) or min(moments) < 0
        if not bad:
            a, b, c = sorted(moments)
            bad = c > a + b + 1e-12 * max(c, 1.0)
        if bad:
            msg = (
                f"{who}{{where}} has principal moments {', '.join(f'{v:.4g}' for v in moments)} kg m^2; "
                "an inertia needs moments >= 0 with each at most the sum of the other two"
            )
            out.append(_finding(design, "contract.invalid_inertia", msg, el))
    return out


def check_contract(design: Design, contract: ModelContract) -> list[Finding]:
    """All violations of ``contract`` by ``design`` (empty list: the design conforms).

    Findings come in the order: required names, gravcomp, options, world welds, actuators, roots,
    massless bodies, frames.
    """
    out = _required(design, contract)
    if contract.forbid_gravcomp:
        out += _gravcomp(design)
    if contract.forbid_option_changes:
        out += _options(design, contract.allowed_options)
    if contract.forbid_world_welds:
        out += _world_welds(design)
    if contract.forbid_actuators:
        out += _actuators(design)
    if contract.forbid_multiple_roots:
        out += _multiple_roots(design)
    if contract.forbid_massless_bodies:
        out += _massless(design)
    if contract.forbid_frames:
        out += _frames(design)
    if contract.forbid_invalid_inertia:
        out += _invalid_inertia(design)
    return out
