"""Named elements of a compiled model or a spec: ids by name, or ``MissingElement`` listing the others.

``element_id(model, "site", "tool_site")`` replaces ``mujoco.mj_name2id``, which answers -1 for a
missing name and leaves the caller an ``IndexError`` three calls later. Kinds are words (``"body"``,
``"site"``, ``"joint"``, ``"geom"``, ``"actuator"``, ``"sensor"``, ``"tendon"``, ``"camera"``,
``"keyframe"``, ...) or ``mujoco.mjtObj`` members.
"""

from __future__ import annotations

from collections.abc import Iterable

import mujoco

from rle_design.errors import ConfigError, MissingElement

__all__ = [
    "element_id",
    "element_ids",
    "element_names",
    "find_body",
    "find_site",
    "has_element",
    "object_type",
]

_OBJ = mujoco.mjtObj

# word -> (object type, name of the count field of MjModel)
_KINDS: dict[str, tuple[mujoco.mjtObj, str]] = {
    "body": (_OBJ.mjOBJ_BODY, "nbody"),
    "joint": (_OBJ.mjOBJ_JOINT, "njnt"),
    "geom": (_OBJ.mjOBJ_GEOM, "ngeom"),
    "site": (_OBJ.mjOBJ_SITE, "nsite"),
    "camera": (_OBJ.mjOBJ_CAMERA, "ncam"),
    "light": (_OBJ.mjOBJ_LIGHT, "nlight"),
    "mesh": (_OBJ.mjOBJ_MESH, "nmesh"),
    "material": (_OBJ.mjOBJ_MATERIAL, "nmat"),
    "texture": (_OBJ.mjOBJ_TEXTURE, "ntex"),
    "pair": (_OBJ.mjOBJ_PAIR, "npair"),
    "exclude": (_OBJ.mjOBJ_EXCLUDE, "nexclude"),
    "equality": (_OBJ.mjOBJ_EQUALITY, "neq"),
    "tendon": (_OBJ.mjOBJ_TENDON, "ntendon"),
    "actuator": (_OBJ.mjOBJ_ACTUATOR, "nu"),
    "sensor": (_OBJ.mjOBJ_SENSOR, "nsensor"),
    "numeric": (_OBJ.mjOBJ_NUMERIC, "nnumeric"),
    "text": (_OBJ.mjOBJ_TEXT, "ntext"),
    "tuple": (_OBJ.mjOBJ_TUPLE, "ntuple"),
    "keyframe": (_OBJ.mjOBJ_KEY, "nkey"),
}
_WORDS = {obj: word for word, (obj, _) in _KINDS.items()}


def object_type(kind: str | mujoco.mjtObj) -> tuple[str, mujoco.mjtObj]:
    """The word and the ``mjtObj`` of an element kind.

    Raises:
        ConfigError: The kind is neither a known word nor a supported ``mjtObj``; lists the words.
    """
    if isinstance(kind, mujoco.mjtObj):
        if kind in _WORDS:
            return _WORDS[kind], kind
        raise ConfigError(
            f"element kind {kind.name} is not supported. Available kinds: {', '.join(_KINDS)}",
            code="scene.unknown_kind",
        )
    if kind not in _KINDS:
        raise ConfigError(
            f"element kind '{kind}' does not exist. Available kinds: {', '.join(_KINDS)}",
            code="scene.unknown_kind",
        )
    return kind, _KINDS[kind][0]


def element_names(model: mujoco.MjModel, kind: str | mujoco.mjtObj) -> list[str]:
    """Names of every element of a kind, in id order (unnamed elements give ``""``)."""
    word, obj = object_type(kind)
    count = int(getattr(model, _KINDS[word][1]))
    return [mujoco.mj_id2name(model, obj, i) or "" for i in range(count)]


def has_element(model: mujoco.MjModel, kind: str | mujoco.mjtObj, name: str) -> bool:
    """Whether the model has an element of that kind named ``name`` (for optional elements)."""
    return mujoco.mj_name2id(model, object_type(kind)[1], name) >= 0


def element_id(
    model: mujoco.MjModel, kind: str | mujoco.mjtObj, name: str, *, code: str | None = None
) -> int:
    """Id of the element ``name`` of a kind in a compiled model.

    Args:
        model: Compiled model.
        kind: Element kind, a word (``"site"``) or an ``mjtObj``.
        name: Element name.
        code: Error code of the ``MissingElement`` (default ``contract.missing_element``).

    Raises:
        MissingElement: No element of that kind has this name; the message lists the available names.
    """
    word, obj = object_type(kind)
    i = mujoco.mj_name2id(model, obj, name)
    if i < 0:
        raise MissingElement(word, name, available=element_names(model, word), code=code)
    return int(i)


def element_ids(
    model: mujoco.MjModel, kind: str | mujoco.mjtObj, names: Iterable[str], *, code: str | None = None
) -> list[int]:
    """Ids of several elements of one kind, in the order of ``names`` (see ``element_id``)."""
    return [element_id(model, kind, n, code=code) for n in names]


def _spec_names(items) -> list[str]:
    return [i.name for i in items if i.name]


def find_site(spec: mujoco.MjSpec, name: str, *, code: str = "contract.missing_site") -> mujoco.MjsSite:
    """Site of a spec by name, or ``MissingElement`` listing the spec's sites."""
    site = spec.site(name)
    if site is None:
        raise MissingElement("site", name, available=_spec_names(spec.sites), code=code)
    return site


def find_body(spec: mujoco.MjSpec, name: str, *, code: str = "contract.missing_body") -> mujoco.MjsBody:
    """Body of a spec by name (``"world"`` is the world body), or ``MissingElement`` listing the bodies."""
    body = spec.worldbody if name == "world" else spec.body(name)
    if body is None:
        raise MissingElement("body", name, available=_spec_names(spec.bodies), code=code)
    return body
