"""Attaching one model to another at a site, every attached name prefixed (dm_control.mjcf style).

The child's root body is placed with its frame on the site's frame; its joints, geoms, sites,
actuators, sensors, assets and keyframes come along, each name prefixed, so two copies of one model
(or two models sharing names such as ``base``) can live in one scene.
"""

from __future__ import annotations

import mujoco

from rle_design.errors import ConfigError, MjcfError
from rle_design.scene.elements import find_body, find_site

__all__ = ["attach", "root_body"]


def root_body(child: mujoco.MjSpec, body: str | None = None) -> mujoco.MjsBody:
    """The body of ``child`` to attach: ``body`` by name, else the single root body.

    Raises:
        MissingElement: ``body`` is not a body of ``child``.
        MjcfError: ``body`` is None and ``child`` has no or several root bodies (code
            ``scene.root_body``).
    """
    if body is not None:
        return find_body(child, body)
    roots = list(child.worldbody.bodies)
    if len(roots) != 1:
        names = ", ".join(b.name or "(unnamed)" for b in roots) or "(none)"
        raise MjcfError(
            f"cannot choose the body to attach: the child has {len(roots)} root bodies ({names}); name one",
            code="scene.root_body",
        )
    return roots[0]


def attach(
    spec: mujoco.MjSpec,
    child: mujoco.MjSpec | mujoco.MjsBody,
    site: str | mujoco.MjsSite,
    prefix: str,
    *,
    body: str | None = None,
) -> mujoco.MjsBody:
    """Attach ``child`` at a site of ``spec``, prefixing every attached name with ``prefix``.

    Args:
        spec: The parent, edited in place.
        child: A spec (its single root body, or ``body``, is attached) or a body of another spec.
        site: Site of ``spec`` (name or element) that carries the child's root frame.
        prefix: Name prefix of the attached elements, e.g. ``"panda/"``; must not be empty.
        body: Root of the attached subtree when ``child`` is a spec with several root bodies.

    Returns:
        The attached body, as a body of ``spec``.

    Raises:
        ConfigError: Empty prefix.
        MissingElement: The site (or ``body``) does not exist; lists the available names.
        MjcfError: MuJoCo refuses the attachment (e.g. a prefix already used), with its message.
    """
    if not prefix:
        raise ConfigError("attach: prefix must not be empty (it keeps attached names unique)")
    target = find_site(spec, site) if isinstance(site, str) else site
    root = root_body(child, body) if isinstance(child, mujoco.MjSpec) else child
    name = root.name  # MuJoCo may rename the root before it refuses
    try:
        return target.attach_body(root, prefix, "")
    except ValueError as exc:
        raise MjcfError(
            f"cannot attach '{name}' with prefix '{prefix}': {exc}", code="scene.attach"
        ) from None
