"""Pinocchio models from MJCF, with a pre-check for the constructs Pinocchio silently drops.

Pinocchio 4.1 ``buildModelFromMJCF`` reads bodies, hinge/slide joints, inertials and sites, but
SILENTLY DROPS joint stiffness/springref, tendons, equality constraints, actuators, ``gravcomp``,
bodies inside ``<frame>`` and every root body after the first. ``precheck_mjcf`` lists those
constructs so a caller can reject them or account for them separately (springs: ``springs.py``).

``model_from_mujoco`` is the robust path used by verifiers: MuJoCo compiles the (validated)
document first, then a kinematic skeleton of the compiled tree (bodies, joints, inertials, sites;
no meshes, includes, defaults or frames) is handed to ``buildModelFromMJCF`` and checked against
MuJoCo joint anchors and axes at the reference configuration.
"""

from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin
from lxml import etree

from rle_design.errors import MjcfError

__all__ = ["DroppedConstruct", "KinematicModel", "model_from_mjcf", "model_from_mujoco", "precheck_mjcf"]


@dataclass(frozen=True)
class DroppedConstruct:
    """An MJCF construct that ``pin.buildModelFromMJCF`` ignores without a warning.

    Attributes:
        code: Stable code, e.g. ``"kinematics.tendon"``.
        element: Tag of the element.
        name: Its name attribute (may be empty).
        line: Source line.
        message: What Pinocchio does with it and how the toolkit accounts for it.
    """

    code: str
    element: str
    name: str
    line: int | None
    message: str


_SPRINGS = frozenset({"kinematics.joint_spring", "kinematics.tendon"})


def precheck_mjcf(xml: str | bytes | etree._Element) -> list[DroppedConstruct]:
    """Constructs of an MJCF document that Pinocchio drops silently.

    Args:
        xml: Document text or parsed root element (includes already inlined).

    Returns:
        One entry per dropped construct, in document order.
    """
    root = (
        xml
        if isinstance(xml, etree._Element)
        else etree.fromstring(xml.encode() if isinstance(xml, str) else xml)
    )
    out: list[DroppedConstruct] = []

    def add(code: str, el, msg: str) -> None:
        out.append(DroppedConstruct(code, str(el.tag), el.get("name", ""), el.sourceline, msg))

    for el in root.iter("joint"):
        if el.getparent() is not None and el.getparent().tag == "default":
            continue
        if float(el.get("stiffness", "0") or 0) != 0.0 or el.get("springref") is not None:
            add("kinematics.joint_spring", el, "joint stiffness/springref dropped; use springs.joint_springs")
    for tag, code, msg in (
        ("tendon", "kinematics.tendon", "tendons dropped; spatial tendon springs via springs.tendon_springs"),
        ("equality", "kinematics.equality", "equality constraints dropped"),
        ("actuator", "kinematics.actuator", "actuators dropped"),
    ):
        for el in root.iter(tag):
            if len(el):
                add(code, el, msg)
    for el in root.iter("body"):
        if el.get("gravcomp") not in (None, "0", "0.0"):
            add("kinematics.gravcomp", el, "gravcomp dropped (gravity compensation by fiat)")
    for el in root.iter("frame"):
        if el.find(".//body") is not None:
            add("kinematics.frame_body", el, "bodies inside <frame> dropped")
    world = root.find("worldbody")
    if world is not None:
        roots = world.findall("body")
        for el in roots[1:]:
            add("kinematics.extra_root", el, "root bodies after the first dropped")
    return out


@dataclass
class KinematicModel:
    """A Pinocchio model aligned with a compiled MuJoCo model (same joint order).

    Attributes:
        model: Pinocchio model (revolute/prismatic joints only, gravity -9.81 z unless MuJoCo differs).
        data: Scratch data.
        joint_names: Names of the actuated joints, in q order.
        mj_joint_ids: MuJoCo joint id of each q coordinate.
        dropped: Constructs of the source that Pinocchio ignored (accounted elsewhere or rejected).
    """

    model: pin.Model
    data: pin.Data
    joint_names: list[str]
    mj_joint_ids: list[int] = field(default_factory=list)
    dropped: list[DroppedConstruct] = field(default_factory=list)

    @property
    def nq(self) -> int:
        return int(self.model.nq)

    def joint_id(self, mj_body_or_joint: str) -> int:
        """Pinocchio joint index by joint name."""
        return int(self.model.getJointId(mj_body_or_joint))


def _fmt(v) -> str:
    return " ".join(f"{float(x):.17g}" for x in np.ravel(v))


def _skeleton_name(m: mujoco.MjModel, kind: mujoco.mjtObj, i: int, prefix: str) -> str:
    """Name of element ``i`` in the skeleton: its own, or ``prefix + id`` when it has none."""
    return mujoco.mj_id2name(m, kind, i) or f"{prefix}{i}"


def _skeleton_tree(m: mujoco.MjModel, carrier: bool) -> etree._Element:
    """The skeleton as an element tree; with ``carrier`` every root body hangs from one massless
    body ``__root__`` at the origin."""
    children: dict[int, list[int]] = {}
    for b in range(1, m.nbody):
        children.setdefault(int(m.body_parentid[b]), []).append(b)
    root = etree.Element("mujoco", model="skeleton")
    etree.SubElement(root, "compiler", angle="radian", inertiafromgeom="false")
    parent = etree.SubElement(root, "worldbody")
    if carrier:
        parent = etree.SubElement(parent, "body", name="__root__")
        etree.SubElement(parent, "inertial", pos="0 0 0", mass="0", diaginertia="0 0 0")

    def name(kind, i, prefix):
        return _skeleton_name(m, kind, i, prefix)

    def emit(b: int, into: etree._Element) -> None:
        body = etree.SubElement(
            into,
            "body",
            name=name(mujoco.mjtObj.mjOBJ_BODY, b, "body"),
            pos=_fmt(m.body_pos[b]),
            quat=_fmt(m.body_quat[b]),
        )
        etree.SubElement(
            body,
            "inertial",
            pos=_fmt(m.body_ipos[b]),
            quat=_fmt(m.body_iquat[b]),
            mass=f"{m.body_mass[b]:.17g}",
            diaginertia=_fmt(m.body_inertia[b]),
        )
        for j in range(m.body_jntadr[b], m.body_jntadr[b] + m.body_jntnum[b]):
            jt = int(m.jnt_type[j])
            if jt not in (mujoco.mjtJoint.mjJNT_HINGE, mujoco.mjtJoint.mjJNT_SLIDE):
                raise MjcfError(
                    f"joint '{name(mujoco.mjtObj.mjOBJ_JOINT, j, 'joint')}' has type {mujoco.mjtJoint(jt).name}; "
                    "only hinge and slide joints are supported",
                    code="kinematics.joint_type",
                    element="joint",
                )
            etree.SubElement(
                body,
                "joint",
                name=name(mujoco.mjtObj.mjOBJ_JOINT, j, "joint"),
                type="hinge" if jt == mujoco.mjtJoint.mjJNT_HINGE else "slide",
                pos=_fmt(m.jnt_pos[j]),
                axis=_fmt(m.jnt_axis[j]),
            )
        for s in range(m.nsite):
            if m.site_bodyid[s] == b:
                etree.SubElement(
                    body,
                    "site",
                    name=name(mujoco.mjtObj.mjOBJ_SITE, s, "site"),
                    pos=_fmt(m.site_pos[s]),
                    quat=_fmt(m.site_quat[s]),
                )
        for c in children.get(b, []):
            emit(c, body)

    for c in children.get(0, []):
        emit(c, parent)
    return root


def skeleton_xml(m: mujoco.MjModel, *, carrier: bool = False) -> str:
    """Kinematic skeleton of a compiled MuJoCo model: bodies, hinge/slide joints, inertials, sites.

    Numbers are written with 17 significant digits, so the skeleton reproduces the compiled model's
    doubles exactly.

    Args:
        m: Compiled model.
        carrier: Hang every root body from one massless body ``__root__`` at the origin.

    Raises:
        MjcfError: A joint type Pinocchio models differently (ball, free) is present.
    """
    return etree.tostring(_skeleton_tree(m, carrier), encoding="unicode")


def _build(path: str) -> pin.Model:
    return pin.buildModelFromMJCF(path)


def model_from_mujoco(m: mujoco.MjModel, *, check_tol: float = 1e-9) -> KinematicModel:
    """Pinocchio model of a compiled MuJoCo model, cross-checked at the reference configuration.

    Several root bodies are supported (all hang from one carrier body at the origin); joint order
    follows MuJoCo. Gravity is copied from ``m.opt.gravity``.

    Raises:
        MjcfError: Unsupported joint type, or joint anchors/axes disagree with MuJoCo by more
            than ``check_tol`` [m] (code ``kinematics.mismatch``).
    """
    # Pinocchio keeps only the first root body and ignores its placement: wrap every root in one
    # massless carrier body at the world origin.
    xml = skeleton_xml(m, carrier=True)
    with tempfile.TemporaryDirectory(prefix="rle_pin_") as tmp:
        path = os.path.join(tmp, "skeleton.xml")
        Path(path).write_text(xml)
        model = _build(path)
    model.gravity.linear = np.asarray(m.opt.gravity, float)
    names = [model.names[j] for j in range(1, model.njoints)]
    # unnamed MuJoCo joints appear as "joint<id>" in the skeleton
    skeleton_ids = {_skeleton_name(m, mujoco.mjtObj.mjOBJ_JOINT, j, "joint"): j for j in range(m.njnt)}
    missing = [n for n in names if n not in skeleton_ids]
    if missing:
        raise MjcfError(
            f"Pinocchio joints {missing} have no MuJoCo joint. Available: {', '.join(skeleton_ids)}",
            code="kinematics.mismatch",
        )
    mj_ids = [skeleton_ids[n] for n in names]
    km = KinematicModel(model, model.createData(), names, mj_ids)
    _crosscheck(km, m, check_tol)
    return km


def _crosscheck(km: KinematicModel, m: mujoco.MjModel, tol: float) -> None:
    d = mujoco.MjData(m)
    mujoco.mj_kinematics(m, d)
    q = np.array([m.qpos0[m.jnt_qposadr[j]] for j in km.mj_joint_ids])
    pin.forwardKinematics(km.model, km.data, q)
    for k, j in enumerate(km.mj_joint_ids):
        oMi = km.data.oMi[k + 1]
        err_p = np.linalg.norm(oMi.translation - d.xanchor[j])
        axis = oMi.rotation @ _local_axis(km.model, k + 1)
        err_a = np.linalg.norm(axis - d.xaxis[j])
        if err_p > tol or err_a > tol:
            raise MjcfError(
                f"Pinocchio and MuJoCo disagree on joint '{km.joint_names[k]}': anchor {err_p:.3g} m, "
                f"axis {err_a:.3g}",
                code="kinematics.mismatch",
                element="joint",
            )


def _local_axis(model: pin.Model, j: int) -> np.ndarray:
    """Unit axis of joint ``j`` in its own frame (revolute or prismatic)."""
    jm = model.joints[j]
    short = jm.shortname()
    for tag, ax in (("X", (1.0, 0, 0)), ("Y", (0, 1.0, 0)), ("Z", (0, 0, 1.0))):
        if short.endswith(tag) and ("RevoluteUnaligned" not in short and "PrismaticUnaligned" not in short):
            return np.array(ax, float)
    return np.asarray(jm.extract().axis, float)


def is_revolute(model: pin.Model, j: int) -> bool:
    """Whether joint ``j`` is revolute (else prismatic)."""
    s = model.joints[j].shortname()
    return "Revolute" in s or s.startswith("JointModelR")


def model_from_mjcf(path: str | os.PathLike, *, allow: frozenset[str] = _SPRINGS) -> KinematicModel:
    """Pinocchio model straight from an MJCF file, refusing constructs Pinocchio would drop.

    Args:
        path: Trusted MJCF file (no untrusted includes: Pinocchio reads them itself).
        allow: Dropped-construct codes that are accepted because the caller accounts for them
            separately (default: joint and tendon springs).

    Raises:
        MjcfError: A dropped construct outside ``allow`` is present (code of the construct).
    """
    text = Path(path).read_bytes()
    dropped = precheck_mjcf(text)
    for dc in dropped:
        if dc.code not in allow:
            raise MjcfError(
                f"{dc.message} (name '{dc.name}')",
                code=dc.code,
                element=dc.element,
                line=dc.line,
                path=str(path),
            )
    model = _build(str(path))
    names = [model.names[j] for j in range(1, model.njoints)]
    return KinematicModel(model, model.createData(), names, [], dropped)
