"""Adversarial artifact corpus: each case builds one bad artifact and names the error code it must
produce and the highest score it may get.

Score bounds: family 08 scores zero for anything that fails loading, and is capped at 0.15 for a
failed validity checkpoint. Family 09 skips the submitted-arm battery of a leader that fails loading
or its contract, but still runs the adapted reference-arm battery with its trim.py (<= 0.20). Faults
of submitted code score at most what the design earns without that code: family 09 keeps motion
clearance, the passive battery and servo headroom (<= 0.50), family 08 loses shelf integration (<= 0.85).
Artifacts are built from the shipped reference solutions, altered in one place each.
"""

from __future__ import annotations

import dataclasses
import os
import re
import shutil
import struct
import zipfile
from collections.abc import Callable
from pathlib import Path

from rle_design.ledger.records import LedgerWriter
from rle_design.ledger.verify import verify_ledger
from rle_tasks.audit.case import Case
from rle_tasks.core.report import ErrorEntry, VerifierReport
from rle_tasks.core.runtime.secrets import Secret
from rle_tasks.core.solutions import materialise

F08, F09, F07 = "08-mobile-base", "09-gello", "07-bin-clearing"
F09_ARMS = ("panda", "ur5e", "xarm7")  # family 09 cases alter all three leaders alike
F09_CODE_CAP = 0.50
F09_DESIGN_CAP = 0.20
F08_CODE_CAP = 0.85
F07_CODE_CAP = 0.1  # a policy that faults in the smoke test is capped at 0.1; later faults end its piles
CODE_FILE = {F08: "controller.py", F09: "trim.py", F07: "policy/__init__.py"}
"""The file of the reference each task's code cases patch."""


# ---------------------------------------------------------------- builders


def _reference(task: str, dst: Path) -> Path:
    """Copy the task's shipped reference (materialised and checksum-checked) into ``dst``."""
    shutil.copytree(materialise(task, "reference"), dst, dirs_exist_ok=True, symlinks=True)
    return dst


def _bases(task: str, root: Path) -> list[Path]:
    """Directories holding the MJCF and code that a case alters."""
    return [root] if task in (F08, F07) else [root / arm for arm in F09_ARMS]


def _xml_name(task: str) -> str:
    return "robot.xml" if task == F08 else "lead.xml"


def _edit_xml(task: str, edit: Callable[[str], str]) -> Callable[[Path], Path]:
    """Copy the reference and apply a text edit to its MJCF (each leader's in family 09)."""

    def build(d: Path) -> Path:
        _reference(task, d)
        for base in _bases(task, d):
            p = base / _xml_name(task)
            p.write_text(edit(p.read_text()))
        return d

    return build


def _replace_xml(task: str, data: bytes | Callable[[bytes], bytes]) -> Callable[[Path], Path]:
    def build(d: Path) -> Path:
        _reference(task, d)
        for base in _bases(task, d):
            p = base / _xml_name(task)
            p.write_bytes(data(p.read_bytes()) if callable(data) else data)
        return d

    return build


def _inject_worldbody(snippet: str) -> Callable[[str], str]:
    return lambda xml: xml.replace("<worldbody>", "<worldbody>\n" + snippet, 1)


def _inject_root(snippet: str) -> Callable[[str], str]:
    """Insert right after the opening <mujoco ...> tag."""

    def edit(xml: str) -> str:
        start = xml.index("<mujoco")
        end = xml.index(">", start) + 1
        return xml[:end] + "\n" + snippet + xml[end:]

    return edit


def _first_body_attr(attr: str) -> Callable[[str], str]:
    """Add an attribute to the first <body ...> of the worldbody."""

    def edit(xml: str) -> str:
        i = xml.index("<body", xml.index("<worldbody>"))
        return xml[: i + 5] + f" {attr}" + xml[i + 5 :]

    return edit


def _mesh_dir(task: str, base: Path) -> Path:
    """Family 09 leaders declare <compiler meshdir="meshes">: mesh files resolve there."""
    return base / "meshes" if task == F09 else base


def _with_file(task: str, rel: str, data: bytes, edit: Callable[[str], str], sparse: int = 0):
    def build(d: Path) -> Path:
        _edit_xml(task, edit)(d)
        for base in _bases(task, d):
            f = _mesh_dir(task, base) / rel
            f.parent.mkdir(parents=True, exist_ok=True)
            f.write_bytes(data)
            if sparse:
                os.truncate(f, sparse)
        return d

    return build


def _with_symlink(task: str, rel: str, target: str, edit: Callable[[str], str]):
    def build(d: Path) -> Path:
        _edit_xml(task, edit)(d)
        for base in _bases(task, d):
            ((_mesh_dir(task, base) if rel.endswith(".stl") else base) / rel).symlink_to(target)
        return d

    return build


def _mesh_ref(file: str) -> Callable[[str], str]:
    return lambda xml: _inject_root(f'<asset><mesh name="evil" file="{file}"/></asset>')(xml).replace(
        "<worldbody>",
        '<worldbody>\n<geom type="mesh" mesh="evil" contype="0" conaffinity="0" mass="0.001"/>',
        1,
    )


def _stl(n_faces: int, tri: tuple = ((0, 0, 0), (1, 0, 0), (0, 1, 0))) -> bytes:
    face = struct.pack("<3f", 0, 0, 1) + b"".join(struct.pack("<3f", *v) for v in tri) + b"\0\0"
    return b"\0" * 80 + struct.pack("<I", n_faces) + face * n_faces


def _code(task: str, patch: str, prepend: bool = False) -> Callable[[Path], Path]:
    """Copy the reference and override a function of the submitted module (later defs win)."""

    def build(d: Path) -> Path:
        _reference(task, d)
        for base in _bases(task, d):
            p = base / CODE_FILE[task]
            src = p.read_text()
            p.write_text(patch + "\n" + src if prepend else src + "\n\n" + patch + "\n")
        return d

    return build


# ---------------------------------------------------------------- ledger cases

LEDGER_TASK = "03-tower"


def _ledger_key(secret: Secret) -> bytes:
    from rle_tasks.core.runtime.devenv import ledger_key

    return ledger_key(secret, LEDGER_TASK)


def _ledger(
    tamper: Callable[[list[bytes]], list[bytes]], *, task: str = LEDGER_TASK, key: bytes | None = None
):
    """A clean 20-step sealed ledger written with the audit secret, then tampered."""

    def build(d: Path) -> Path:
        from rle_tasks.audit.case import AUDIT_SECRET

        path = d / "ledger.jsonl"
        w = LedgerWriter(path, key or _ledger_key(AUDIT_SECRET), task)
        w.append("reset", {"seed": 0, "steps": 1})
        for i in range(19):
            action = struct.pack("<2d", 0.1 * i, 0.0).hex()
            w.append_steps([action], steps=i + 2, sim_time=0.02 * (i + 1), wall=0.0)
        w.seal(20)
        lines = path.read_bytes().splitlines(keepends=True)
        path.write_bytes(b"".join(tamper(lines)))
        return d

    return build


def _run_ledger(artifact: Path, secret: Secret) -> VerifierReport:
    verdict = verify_ledger(artifact / "ledger.jsonl", _ledger_key(secret), LEDGER_TASK)
    errors = () if verdict.valid else (ErrorEntry(verdict.code, verdict.message, "ledger.jsonl"),)
    return VerifierReport(
        task_id=LEDGER_TASK, family="03", workflow="interactive_control", valid=verdict.valid, errors=errors
    )


def _alter(lines: list[bytes]) -> list[bytes]:
    """Change one hex digit of the action recorded on line 6 (the MAC no longer matches)."""
    i = lines[5].index(b'"actions":["') + len(b'"actions":["')
    digit = b"1" if lines[5][i : i + 1] != b"1" else b"2"
    lines[5] = lines[5][:i] + digit + lines[5][i + 1 :]
    return lines


def _ledger_case(name: str, expect: str, build) -> Case:
    return Case(f"ledger/{name}", LEDGER_TASK, expect, build, run=_run_ledger, wall_cap_s=5.0)


def ledger_cases() -> list[Case]:
    return [
        _ledger_case("missing", "ledger.missing", lambda d: d),
        _ledger_case("empty", "ledger.empty", _ledger(lambda ls: [])),
        _ledger_case("unsealed", "ledger.unsealed", _ledger(lambda ls: ls[:-1])),
        _ledger_case("truncated_mid_record", "ledger.truncated", _ledger(lambda ls: ls[:-1] + [ls[-1][:40]])),
        _ledger_case("truncated_middle", "ledger.truncated", _ledger(lambda ls: ls[:5] + ls[9:])),
        _ledger_case("reordered", "ledger.reordered", _ledger(lambda ls: ls[:3] + [ls[4], ls[3]] + ls[5:])),
        _ledger_case("altered_field", "ledger.altered", _ledger(_alter)),
        _ledger_case("replayed_seal", "ledger.replayed_seal", _ledger(lambda ls: ls + [ls[-1]])),
        _ledger_case("after_seal", "ledger.after_seal", _ledger(lambda ls: ls + [ls[3]])),
        _ledger_case(
            "malformed_line", "ledger.malformed", _ledger(lambda ls: ls[:2] + [b"not json\n"] + ls[2:])
        ),
        _ledger_case("forged_key", "ledger.forged_key", _ledger(lambda ls: ls, key=b"k" * 32)),
        _ledger_case("other_task", "ledger.wrong_task", _ledger(lambda ls: ls, task="03-cantilever")),
        _ledger_case(
            "other_secret",
            "ledger.forged_key",
            lambda d: _ledger(lambda ls: ls, key=_ledger_key(Secret(b"another-secret", public=False)))(d),
        ),
    ]


# ---------------------------------------------------------------- XML and mesh cases

BOMB = (
    '<?xml version="1.0"?>\n<!DOCTYPE lolz [<!ENTITY lol "lol">'
    + "".join(
        f'<!ENTITY lol{i} "{("&lol" + (str(i - 1) if i > 1 else "") + ";") * 10}">' for i in range(1, 10)
    )
    + ']>\n<mujoco model="bomb"><worldbody><body name="&lol9;"/></worldbody></mujoco>\n'
).encode()
XXE = b'<?xml version="1.0"?><!DOCTYPE m [<!ENTITY x SYSTEM "file:///etc/passwd">]><mujoco model="&x;"/>'


def xml_cases(task: str) -> list[Case]:
    cap = 0.0 if task == F08 else F09_DESIGN_CAP
    return [dataclasses.replace(c, max_score=cap) for c in _xml_cases(task)]


def _xml_cases(task: str) -> list[Case]:
    t = task[:3]
    return [
        Case(f"xml/{t}entity_bomb", task, "mjcf.entity", _replace_xml(task, BOMB)),
        Case(f"xml/{t}external_entity", task, "mjcf.entity", _replace_xml(task, XXE)),
        Case(
            f"xml/{t}deep_nesting",
            task,
            "mjcf.too_deep",
            _replace_xml(
                task, b"<mujoco><worldbody>" + b"<body>" * 5000 + b"</body>" * 5000 + b"</worldbody></mujoco>"
            ),
        ),
        Case(
            f"xml/{t}attribute_50mb",
            task,
            "artifact.too_large",
            _replace_xml(task, b'<mujoco model="' + b"A" * (50 << 20) + b'"/>'),
        ),
        Case(
            f"xml/{t}invalid_utf8",
            task,
            "mjcf.parse",
            _replace_xml(task, b'<mujoco model="\xff\xfe\xfa"></mujoco>'),
        ),
        Case(
            f"xml/{t}truncated",
            task,
            "mjcf.parse",
            _replace_xml(task, lambda data: data[: len(data) // 2]),
        ),
        Case(f"xml/{t}empty_file", task, "mjcf.parse", _replace_xml(task, b"")),
        Case(
            f"xml/{t}not_mjcf",
            task,
            "mjcf.not_mjcf",
            _replace_xml(task, b'<robot name="urdf"><link name="a"/></robot>'),
        ),
        Case(
            f"xml/{t}schema_error",
            task,
            "mjcf.schema",
            _inject_worldbody_edit(task, '<geom type="box" size="-1 x 0.1"/>'),
        ),
        Case(
            f"xml/{t}include_absolute",
            task,
            "artifact.path_absolute",
            _edit_xml(task, _inject_root('<include file="/etc/passwd"/>')),
        ),
        Case(
            f"xml/{t}include_dotdot",
            task,
            "artifact.path_escape",
            _edit_xml(task, _inject_root('<include file="../../outside.xml"/>')),
        ),
        Case(
            f"xml/{t}include_symlink_out",
            task,
            "artifact.symlink_escape",
            _with_symlink(task, "inc.xml", "/etc/hostname", _inject_root('<include file="inc.xml"/>')),
        ),
        Case(
            f"xml/{t}mesh_etc_passwd",
            task,
            "artifact.path_absolute",
            _edit_xml(task, _mesh_ref("/etc/passwd")),
        ),
        Case(
            f"xml/{t}mesh_dotdot", task, "artifact.path_escape", _edit_xml(task, _mesh_ref("../../../x.stl"))
        ),
        Case(
            f"xml/{t}mesh_symlink_out",
            task,
            "artifact.symlink_escape",
            _with_symlink(task, "evil.stl", "/etc/passwd", _mesh_ref("evil.stl")),
        ),
        Case(
            f"xml/{t}texture_escape",
            task,
            "artifact.path_escape",
            _edit_xml(task, _inject_root('<asset><texture name="t" type="2d" file="../../t.png"/></asset>')),
        ),
        Case(
            f"xml/{t}hfield_absolute",
            task,
            "artifact.path_absolute",
            _edit_xml(
                task, _inject_root('<asset><hfield name="h" file="/dev/zero" size="1 1 1 1"/></asset>')
            ),
        ),
        Case(
            f"xml/{t}meshdir_absolute",
            task,
            "artifact.path_absolute",
            _edit_xml(task, lambda x: _mesh_ref("passwd")(_inject_root('<compiler meshdir="/etc"/>')(x))),
        ),
        Case(
            f"xml/{t}plugin",
            task,
            "mjcf.forbidden_element",
            _edit_xml(
                task, _inject_root('<extension><plugin plugin="mujoco.elasticity.cable"/></extension>')
            ),
        ),
        Case(
            f"mesh/{t}zip_as_stl",
            task,
            "mesh.invalid",
            _with_file(task, "evil.stl", _zip_bytes(), _mesh_ref("evil.stl")),
        ),
        Case(
            f"mesh/{t}ascii_stl",
            task,
            "mesh.invalid",
            _with_file(task, "evil.stl", b"solid x\nendsolid x\n", _mesh_ref("evil.stl")),
        ),
        Case(
            f"mesh/{t}10m_faces_stl",
            task,
            "artifact.too_large",
            _with_file(task, "big.stl", _stl(1)[:84], _mesh_ref("big.stl"), sparse=84 + 50 * 10_000_000),
        ),
        Case(
            f"mesh/{t}2m_faces_obj",
            task,
            "mesh.too_many_faces",
            _with_file(
                task,
                "big.obj",
                b"v 0 0 0\nv 1 0 0\nv 0 1 0\n" + b"f 1 2 3\n" * 2_100_000,
                _mesh_ref("big.obj"),
            ),
        ),
        Case(
            f"mesh/{t}degenerate",
            task,
            "mjcf.compile",
            _with_file(task, "flat.stl", _stl(4, ((0, 0, 0), (1, 0, 0), (2, 0, 0))), _mesh_ref("flat.stl")),
        ),
    ]


def _inject_worldbody_edit(task: str, snippet: str):
    return _edit_xml(task, _inject_worldbody(snippet))


def _zip_bytes() -> bytes:
    import io

    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as z:
        z.writestr("payload.txt", "x" * 1000)
    return buf.getvalue()


def misc_cases() -> list[Case]:
    return [
        Case("artifact/f08_missing_dir", F08, "artifact.missing_dir", lambda d: d / "does-not-exist"),
        Case("artifact/f08_empty_dir", F08, "artifact.missing_file", lambda d: d),
        Case("artifact/f09_empty_dir", F09, "artifact.missing_robot", lambda d: d),
    ]


# ---------------------------------------------------------------- physics cheats


def physics_cases() -> list[Case]:
    f9 = [
        ("gravcomp", "contract.gravcomp", _first_body_attr('gravcomp="1"')),
        ("gravity_changed", "contract.option_changed", _inject_root('<option gravity="0 0 -1"/>')),
        ("timestep_changed", "contract.option_changed", _inject_root('<option timestep="0.0001"/>')),
        ("integrator_changed", "contract.option_changed", _inject_root('<option integrator="RK4"/>')),
        ("weld_to_world", "contract.world_weld", _weld("weld")),
        ("connect_to_world", "contract.world_weld", _weld("connect")),
        ("actuator", "contract.actuator", _actuator),
        (
            "second_root_body",
            "contract.multiple_roots",
            _inject_worldbody('<body name="extra"><geom size="0.01" mass="0.01"/></body>'),
        ),
        ("massless_body", "mjcf.compile", _massless),
        (
            "tendon_friction",
            "contract.tendon_friction",
            _inject_root(
                '<tendon><fixed name="hold" frictionloss="1.2"><joint joint="j2" coef="1"/></fixed></tendon>'
            ),
        ),
        (
            "tendon_damping",
            "contract.tendon_damping",
            lambda xml: xml.replace(
                '<spatial name="shoulder_spring"', '<spatial name="shoulder_spring" damping="100"', 1
            ),
        ),
        (
            "geom_on_stock_body",
            "contract.stock_body_addition",
            lambda xml: xml.replace(
                '<geom name="link2_shell"',
                '<geom name="dense_extra" type="box" size="0.01 0.01 0.01" density="100000" contype="0" '
                'conaffinity="0"/><geom name="link2_shell"',
                1,
            ),
        ),
        (
            "extra_root_with_joint",
            "contract.extra_joint",
            _inject_worldbody(
                '<body name="extra" pos="0.3 0 0.1"><joint name="extra_j" axis="0 1 0"/>'
                '<geom size="0.02" mass="0.1"/></body>'
            ),
        ),
        (
            "floating_counterweight",
            "contract.floating_part",
            lambda xml: re.sub(r'<geom name="counterweight1_rod"[^>]*/>', "", xml, count=1),
        ),
        (
            "spring_end_in_mid_air",
            "contract.spring_anchor",
            lambda xml: xml.replace(
                '<site name="spring_anchor" pos="0 0 0"', '<site name="spring_anchor" pos="0.08 0.08 0.08"', 1
            ),
        ),
        (
            "spring_through_the_arm",
            "contract.spring_path",
            _inject_root(
                # a catalog spring on a slack cable: only its path is at fault
                '<tendon><spatial name="long_spring" stiffness="717.05" springlength="0 2">'
                '<site site="mount_site"/><site site="handle_site"/></spatial></tendon>'
            ),
        ),
        ("ideal_spring", "contract.spring_catalog", _spring_attr("stiffness", "950")),
        ("overloaded_spring", "contract.spring_overload", _spring_attr("stiffness", "939.852")),
        ("pushing_spring", "contract.spring_push", _spring_attr("springlength", "0.03")),
        (
            "ideal_torsion_spring",
            "contract.spring_catalog",
            lambda xml: xml.replace('<joint name="j2"', '<joint name="j2" stiffness="0.5"', 1),
        ),
        (
            "weightless_strut",
            "contract.underweight_part",
            _inside_first_body(
                '<body name="strut"><geom type="box" size="0.05 0.01 0.01" mass="0.0001"/></body>'
            ),
        ),
        (
            "negative_inertia",
            "contract.invalid_inertia",
            _inside_first_body(
                '<body name="neg"><inertial pos="0 0 0" mass="0.1" diaginertia="-1 1 1"/></body>'
            ),
        ),
        (
            "impossible_inertia",
            "contract.invalid_inertia",
            _inside_first_body(
                '<body name="odd"><inertial pos="0 0 0" mass="0.1" diaginertia="1e-4 1e-4 1"/></body>'
            ),
        ),
    ]
    cases = [
        Case(f"physics/f09_{n}", F09, code, _edit_xml(F09, edit), max_score=F09_DESIGN_CAP)
        for n, code, edit in f9
    ]
    f8 = [
        ("gravcomp", "contract.gravcomp", _first_body_attr('gravcomp="1"')),
        ("gravity_changed", "contract.option_changed", _inject_root('<option gravity="0 0 -5"/>')),
        ("weld_to_world", "contract.world_weld", _weld("weld")),
        (
            "battery_in_mid_air",
            "f08.floating_part",
            lambda xml: re.sub(
                r'(<body name="battery" pos="[^ ]+ [^ ]+ )([^"]+)"', r'\g<1>0.2"', xml, count=1
            ),
        ),
        (
            "inertial_below_floor",
            "f08.inertial_mismatch",
            # the reference chassis' own mass, declared 0.5 m below its frame (under the floor)
            lambda xml: re.sub(
                r'(<body name="chassis"[^>]*>)',
                r'\1<inertial pos="0 0 -0.5" mass="6.8904" diaginertia="0.5 0.5 0.5"/>',
                xml,
                count=1,
            ),
        ),
    ]
    cases += [
        Case(f"physics/f08_{n}", F08, code, _edit_xml(F08, edit), max_score=0.15) for n, code, edit in f8
    ]
    return cases


def _spring_attr(attr: str, value: str) -> Callable[[str], str]:
    """Set one attribute of the reference's shoulder spring (the catalog spring becomes an ideal one,
    an under-rated one, or one whose cable would push)."""

    def edit(xml: str) -> str:
        return re.sub(
            rf'(<spatial name="shoulder_spring"[^>]*? {attr}=")[^"]*"', rf'\g<1>{value}"', xml, count=1
        )

    return edit


def _first_body_name(xml: str) -> str:
    i = xml.index("<body", xml.index("<worldbody>"))
    j = xml.index('name="', i) + 6
    return xml[j : xml.index('"', j)]


def _weld(kind: str) -> Callable[[str], str]:
    def edit(xml: str) -> str:
        body = _first_body_name(xml)
        anchor = ' anchor="0 0 0"' if kind == "connect" else ""
        return xml.replace("</mujoco>", f'<equality><{kind} body1="{body}"{anchor}/></equality>\n</mujoco>')

    return edit


def _actuator(xml: str) -> str:
    i = xml.index("<joint", xml.index("<worldbody>"))
    j = xml.index('name="', i) + 6
    joint = xml[j : xml.index('"', j)]
    return xml.replace("</mujoco>", f'<actuator><motor joint="{joint}" gear="1"/></actuator>\n</mujoco>')


def _massless(xml: str) -> str:
    """A moving body with no mass (a hinge with nothing on it): MuJoCo refuses to compile it."""
    i = xml.index("<joint", xml.index("<worldbody>"))
    return (
        xml[:i] + '<body name="ghost" pos="0 0 0.01"><joint name="ghost_j" axis="0 0 1"/></body>\n' + xml[i:]
    )


def _inside_first_body(snippet: str) -> Callable[[str], str]:
    def edit(xml: str) -> str:
        i = xml.index("<joint", xml.index("<worldbody>"))
        return xml[:i] + snippet + "\n" + xml[i:]

    return edit


# ---------------------------------------------------------------- submitted code

HOSTILE = {
    "import_crash": ("raise RuntimeError('boom at import')", "sandbox.import_error", True),
    "monkeypatch_verifier": (
        "import rle_tasks.core.report as _r\n_r.Checkpoint.__post_init__ = lambda self: None",
        "sandbox.import_error",
        True,
    ),
    "hang": (
        "def {fn}(*a, **k):\n    import threading\n    threading.Event().wait()",
        "sandbox.timeout",
        False,
    ),
    "busy_loop": ("def {fn}(*a, **k):\n    while True:\n        pass", "sandbox.timeout", False),
    "sleep_past_cap": ("def {fn}(*a, **k):\n    import time\n    time.sleep(3600)", "sandbox.timeout", False),
    "memory_bomb": ("def {fn}(*a, **k):\n    x = bytearray(64 << 30)\n    return x", "sandbox.memory", False),
    "fork_bomb": (
        "def {fn}(*a, **k):\n    import os\n    while True:\n        os.fork()",
        "sandbox.forbidden",
        False,
    ),
    "read_secret": (
        "def {fn}(*a, **k):\n    import os\n    return os.environ['RLE_SECRET']",
        "sandbox.exception",
        False,
    ),
    "read_verifier_files": (
        "def {fn}(*a, **k):\n    return open('/proc/1/environ', 'rb').read().decode()",
        "sandbox.forbidden",
        False,
    ),
    "write_outside": (
        "def {fn}(*a, **k):\n    open('/tmp/rle_planted_reward.json', 'w').write('{{\"reward\": 1}}')",
        "sandbox.forbidden",
        False,
    ),
    "socket": (
        "def {fn}(*a, **k):\n    import socket\n    socket.create_connection(('127.0.0.1', 9))",
        "sandbox.forbidden",
        False,
    ),
    "signal_parent": (
        "def {fn}(*a, **k):\n    import os\n    os.kill(os.getppid(), 9)",
        "sandbox.forbidden",
        False,
    ),
    "segfault": (
        "def {fn}(*a, **k):\n    import os, signal\n    os.kill(os.getpid(), signal.SIGSEGV)",
        "sandbox.crash",
        False,
    ),
    "sys_exit": ("def {fn}(*a, **k):\n    import sys\n    sys.exit(0)", "sandbox.exit", False),
    "os_exit": ("def {fn}(*a, **k):\n    import os\n    os._exit(3)", "sandbox.exit", False),
    "print_megabytes": (
        "def {fn}(*a, **k):\n    import sys\n    sys.stdout.write('x' * (64 << 20))\n    return _orig_{fn}(*a, **k)",
        "sandbox.output_flood",
        False,
    ),
    "huge_reply": (
        "def {fn}(*a, **k):\n    import numpy as np\n    return np.zeros(40_000_000)",
        "sandbox.output_too_large",
        False,
    ),
    "return_nan": (
        "def {fn}(*a, **k):\n    import numpy as np\n    return np.full(np.shape({like}), np.nan)",
        "sandbox.non_finite",
        False,
    ),
    "return_inf": (
        "def {fn}(*a, **k):\n    import numpy as np\n    return np.full(np.shape({like}), np.inf)",
        "sandbox.non_finite",
        False,
    ),
    "return_string": ("def {fn}(*a, **k):\n    return 'not an array'", "sandbox.bad_type", False),
    "wrong_shape": (
        "def {fn}(*a, **k):\n    import numpy as np\n    return np.zeros((np.size({like}) + 1,))",
        "sandbox.bad_shape",
        False,
    ),
    "raise_midway": (
        "_calls = [0]\ndef {fn}(*a, **k):\n    _calls[0] += 1\n    if _calls[0] > 3:\n"
        "        raise ValueError('controller lost track')\n    return _orig_{fn}(*a, **k)",
        "sandbox.exception",
        False,
    ),
}


def code_cases(task: str, fn: str, like: str, cap: float) -> list[Case]:
    cases = []
    for name, (src, code, prepend) in HOSTILE.items():
        patch = src.format(fn=fn, like=like)
        if name in ("raise_midway", "print_megabytes"):
            patch = f"_orig_{fn} = {fn}\n" + patch
        cases.append(
            Case(
                f"code/{task[:2]}_{name}",
                task,
                code,
                _code(task, patch, prepend),
                max_score=cap,
                wall_cap_s=120,
            )
        )
    return cases


F07_HOSTILE = {
    "read_parent_environ": (
        "def act(*a, **k):\n    import os\n    return open(f'/proc/{os.getppid()}/environ', 'rb').read()",
        "sandbox.forbidden",
    ),
    "read_parent_memory": (
        "def act(*a, **k):\n    import os\n    return open(f'/proc/{os.getppid()}/mem', 'rb').read(64)",
        "sandbox.forbidden",
    ),
    "import_verifier": (
        "def act(*a, **k):\n    from rle_tasks.f07_bin_clearing.verifier import hidden_piles\n    return hidden_piles",
        "sandbox.exception",
    ),
    "wrong_action_length": (
        "def act(*a, **k):\n    import numpy as np\n    return np.zeros(7)",
        "sandbox.bad_shape",
    ),
}
"""Family 07 policies that look for ground truth (the parent's environment or memory, the verifier's
hidden piles) or act out of contract."""


F07_GENERIC = ("import_crash", "hang", "memory_bomb", "read_verifier_files", "return_nan", "raise_midway")
"""Sandbox faults also covered by families 08 and 09: family 07 keeps one per class its protocol maps."""


def f07_cases() -> list[Case]:
    generic = code_cases(F07, "act", "list(a[0]['q']) + [0.0]", F07_CODE_CAP)
    out = [c for c in generic if c.name.split("_", 1)[1] in F07_GENERIC]
    out += [
        Case(f"code/07_{name}", F07, code, _code(F07, src), max_score=F07_CODE_CAP, wall_cap_s=120)
        for name, (src, code) in F07_HOSTILE.items()
    ]
    out.append(Case("artifact/f07_empty_dir", F07, "f07.no_policy", lambda d: d))
    return out


def cases() -> list[Case]:
    out = xml_cases(F08) + xml_cases(F09) + misc_cases() + physics_cases()
    out += code_cases(F09, "feedforward", "a[0]", F09_CODE_CAP)
    out += code_cases(F08, "control", "a[3]", F08_CODE_CAP)
    out += f07_cases()
    out += ledger_cases()
    from rle_tasks.audit.generated import generated_cases

    out += generated_cases(F09, _edit_xml, F09_DESIGN_CAP) + generated_cases(F08, _edit_xml, 0.15)
    return out + family_cases()


def family_cases() -> list[Case]:
    """The cases each family keeps beside its tasks (``rle_tasks/<family>/audit.py``: ``cases()``)."""
    import importlib
    import pkgutil

    import rle_tasks

    out: list[Case] = []
    for mod in sorted(m.name for m in pkgutil.iter_modules(rle_tasks.__path__) if m.name[:1] == "f"):
        if importlib.util.find_spec(f"rle_tasks.{mod}.audit") is not None:
            out += importlib.import_module(f"rle_tasks.{mod}.audit").cases()
    return out
