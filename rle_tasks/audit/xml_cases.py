"""The MJCF and mesh cases every task with a submitted MJCF gets (families 08 and 09): entity bombs,
paths out of the artifact, links, oversized and malformed files, forbidden elements."""

from __future__ import annotations

import dataclasses
import io
import zipfile

from rle_tasks.audit.artifacts import (
    Target,
    edit_xml,
    inject_root,
    inject_worldbody,
    mesh_ref,
    replace_xml,
    stl,
    with_file,
    with_symlink,
)
from rle_tasks.audit.case import Case

__all__ = ["BOMB", "XXE", "xml_cases"]

BOMB = (
    '<?xml version="1.0"?>\n<!DOCTYPE lolz [<!ENTITY lol "lol">'
    + "".join(
        f'<!ENTITY lol{i} "{("&lol" + (str(i - 1) if i > 1 else "") + ";") * 10}">' for i in range(1, 10)
    )
    + ']>\n<mujoco model="bomb"><worldbody><body name="&lol9;"/></worldbody></mujoco>\n'
).encode()
XXE = b'<?xml version="1.0"?><!DOCTYPE m [<!ENTITY x SYSTEM "file:///etc/passwd">]><mujoco model="&x;"/>'


def xml_cases(target: Target, max_score: float) -> list[Case]:
    """The MJCF and mesh cases of a task whose submission is an MJCF, each bounded by ``max_score``."""
    task, t = target.task, target.prefix
    cases = [
        Case(f"xml/{t}entity_bomb", task, "mjcf.entity", replace_xml(target, BOMB)),
        Case(f"xml/{t}external_entity", task, "mjcf.entity", replace_xml(target, XXE)),
        Case(
            f"xml/{t}deep_nesting",
            task,
            "mjcf.too_deep",
            replace_xml(
                target,
                b"<mujoco><worldbody>" + b"<body>" * 5000 + b"</body>" * 5000 + b"</worldbody></mujoco>",
            ),
        ),
        Case(
            f"xml/{t}attribute_50mb",
            task,
            "artifact.too_large",
            replace_xml(target, b'<mujoco model="' + b"A" * (50 << 20) + b'"/>'),
        ),
        Case(
            f"xml/{t}invalid_utf8",
            task,
            "mjcf.parse",
            replace_xml(target, b'<mujoco model="\xff\xfe\xfa"></mujoco>'),
        ),
        Case(
            f"xml/{t}truncated",
            task,
            "mjcf.parse",
            replace_xml(target, lambda data: data[: len(data) // 2]),
        ),
        Case(f"xml/{t}empty_file", task, "mjcf.parse", replace_xml(target, b"")),
        Case(
            f"xml/{t}not_mjcf",
            task,
            "mjcf.not_mjcf",
            replace_xml(target, b'<robot name="urdf"><link name="a"/></robot>'),
        ),
        Case(
            f"xml/{t}schema_error",
            task,
            "mjcf.schema",
            edit_xml(target, inject_worldbody('<geom type="box" size="-1 x 0.1"/>')),
        ),
        Case(
            f"xml/{t}include_absolute",
            task,
            "artifact.path_absolute",
            edit_xml(target, inject_root('<include file="/etc/passwd"/>')),
        ),
        Case(
            f"xml/{t}include_dotdot",
            task,
            "artifact.path_escape",
            edit_xml(target, inject_root('<include file="../../outside.xml"/>')),
        ),
        Case(
            f"xml/{t}include_symlink_out",
            task,
            "artifact.symlink_escape",
            with_symlink(target, "inc.xml", "/etc/hostname", inject_root('<include file="inc.xml"/>')),
        ),
        Case(
            f"xml/{t}mesh_etc_passwd",
            task,
            "artifact.path_absolute",
            edit_xml(target, mesh_ref("/etc/passwd")),
        ),
        Case(
            f"xml/{t}mesh_dotdot", task, "artifact.path_escape", edit_xml(target, mesh_ref("../../../x.stl"))
        ),
        Case(
            f"xml/{t}mesh_symlink_out",
            task,
            "artifact.symlink_escape",
            with_symlink(target, "evil.stl", "/etc/passwd", mesh_ref("evil.stl")),
        ),
        Case(
            f"xml/{t}texture_escape",
            task,
            "artifact.path_escape",
            edit_xml(target, inject_root('<asset><texture name="t" type="2d" file="../../t.png"/></asset>')),
        ),
        Case(
            f"xml/{t}hfield_absolute",
            task,
            "artifact.path_absolute",
            edit_xml(
                target, inject_root('<asset><hfield name="h" file="/dev/zero" size="1 1 1 1"/></asset>')
            ),
        ),
        Case(
            f"xml/{t}meshdir_absolute",
            task,
            "artifact.path_absolute",
            edit_xml(target, lambda x: mesh_ref("passwd")(inject_root('<compiler meshdir="/etc"/>')(x))),
        ),
        Case(
            f"xml/{t}plugin",
            task,
            "mjcf.forbidden_element",
            edit_xml(
                target, inject_root('<extension><plugin plugin="mujoco.elasticity.cable"/></extension>')
            ),
        ),
        Case(
            f"mesh/{t}zip_as_stl",
            task,
            "mesh.invalid",
            with_file(target, "evil.stl", zip_bytes(), mesh_ref("evil.stl")),
        ),
        Case(
            f"mesh/{t}ascii_stl",
            task,
            "mesh.invalid",
            with_file(target, "evil.stl", b"solid x\nendsolid x\n", mesh_ref("evil.stl")),
        ),
        Case(
            f"mesh/{t}10m_faces_stl",
            task,
            "artifact.too_large",
            with_file(target, "big.stl", stl(1)[:84], mesh_ref("big.stl"), sparse=84 + 50 * 10_000_000),
        ),
        Case(
            f"mesh/{t}2m_faces_obj",
            task,
            "mesh.too_many_faces",
            with_file(
                target,
                "big.obj",
                b"v 0 0 0\nv 1 0 0\nv 0 1 0\n" + b"f 1 2 3\n" * 2_100_000,
                mesh_ref("big.obj"),
            ),
        ),
        Case(
            f"mesh/{t}degenerate",
            task,
            "mjcf.compile",
            with_file(target, "flat.stl", stl(4, ((0, 0, 0), (1, 0, 0), (2, 0, 0))), mesh_ref("flat.stl")),
        ),
    ]
    return [dataclasses.replace(c, max_score=max_score) for c in cases]


def zip_bytes() -> bytes:
    """A small zip archive (what an STL loader must refuse)."""
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as z:
        z.writestr("payload.txt", "x" * 1000)
    return buf.getvalue()
