"""Changes of MuJoCo's physics options in a design: every ``<option>`` attribute and ``<flag>`` whose
compiled value differs from MuJoCo's default, named with both values (``contract.option_changed``)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import mujoco
import numpy as np

if TYPE_CHECKING:
    from rle_design.mjcf.loader import Design

# MjsOption field -> (XML element, XML attribute)
_OPTION_FIELDS = {
    "timestep": "timestep",
    "impratio": "impratio",
    "tolerance": "tolerance",
    "ls_tolerance": "ls_tolerance",
    "noslip_tolerance": "noslip_tolerance",
    "ccd_tolerance": "ccd_tolerance",
    "gravity": "gravity",
    "wind": "wind",
    "magnetic": "magnetic",
    "density": "density",
    "viscosity": "viscosity",
    "o_margin": "o_margin",
    "o_solref": "o_solref",
    "o_solimp": "o_solimp",
    "o_friction": "o_friction",
    "integrator": "integrator",
    "cone": "cone",
    "jacobian": "jacobian",
    "solver": "solver",
    "iterations": "iterations",
    "ls_iterations": "ls_iterations",
    "noslip_iterations": "noslip_iterations",
    "ccd_iterations": "ccd_iterations",
    "sdf_iterations": "sdf_iterations",
    "sdf_initpoints": "sdf_initpoints",
    "disableactuator": "actuatorgroupdisable",
    "disableflags": "flag",
    "enableflags": "flag",
}


def _fmt(v) -> str:
    arr = np.atleast_1d(np.asarray(v, dtype=float))
    return " ".join(f"{x:g}" for x in arr)


def _flag_bits(enum, prefix: str) -> dict[int, str]:
    return {
        int(v): k[len(prefix) :].lower()
        for k, v in enum.__members__.items()
        if k.startswith(prefix) and not k.startswith("mjN")
    }


def _flag_changes(old: int, new: int, enum, prefix: str, on: str, off: str) -> list[tuple[str, str, str]]:
    """(flag name, default state, new state) for each bit that differs."""
    return [
        (name, on if old & bit else off, on if new & bit else off)
        for bit, name in _flag_bits(enum, prefix).items()
        if (old ^ new) & bit
    ]


def option_changes(design: Design, allowed: tuple[str, ...]) -> list[tuple[str, object]]:
    """(message, element) for each ``<option>`` value or ``<flag>`` that differs from MuJoCo's default
    and is not in ``allowed`` (``MjsOption`` fields, XML attributes, ``"flag.<name>"``, or ``"flag"``);
    the message holds ``{where}`` for the element's place, the element is the last one that sets it."""
    default, spec = mujoco.MjSpec().option, design.spec.option
    root = design.tree.getroot()
    options = list(root.iter("option"))
    flags = list(root.iter("flag"))
    shown_allowed = ", ".join(allowed) or "(none)"
    out = []
    for fld, attr in _OPTION_FIELDS.items():
        old, new = getattr(default, fld), getattr(spec, fld)
        if fld in allowed or attr in allowed or np.array_equal(np.asarray(old), np.asarray(new)):
            continue
        if attr == "flag":
            enum, prefix = (
                (mujoco.mjtDisableBit, "mjDSBL_")
                if fld == "disableflags"
                else (mujoco.mjtEnableBit, "mjENBL_")
            )
            on, off = ("disable", "enable") if fld == "disableflags" else ("enable", "disable")
            for name, was, now in _flag_changes(int(old), int(new), enum, prefix, on, off):
                if f"flag.{name}" in allowed:
                    continue
                el = next(
                    (f for f in reversed(flags) if f.get(name) is not None), flags[-1] if flags else None
                )
                msg = f"<flag> {name}{{where}} changed from {was} (default) to {now}; allowed changes: {shown_allowed}"
                out.append((msg, el))
            continue
        el = next((o for o in reversed(options) if o.get(attr) is not None), options[-1] if options else None)
        msg = (
            f"<option> {attr}{{where}} changed from {_fmt(old)} (default) to {_fmt(new)}; "
            f"allowed changes: {shown_allowed}"
        )
        out.append((msg, el))
    return out
