"""Hostile artifacts: each gives a specific error code naming the file and element, never a traceback."""

import io
import os
import zipfile

import pytest
import trimesh

from rle_design.errors import MjcfError, RleError, UnsafeArtifact
from rle_design.mjcf.loader import LoadLimits, load_design

STL = trimesh.creation.box([0.1, 0.1, 0.1]).export(file_type="stl")


def mesh_xml(file: str) -> str:
    return (
        "<mujoco>\n"
        "  <asset>\n"
        f'    <mesh name="m" file="{file}"/>\n'
        "  </asset>\n"
        '  <worldbody><body><geom type="mesh" mesh="m"/></body></worldbody>\n'
        "</mujoco>\n"
    )


def load_error(root, limits: LoadLimits | None = None) -> RleError:
    with pytest.raises(RleError) as info:
        load_design(root, "robot.xml", limits or LoadLimits())
    return info.value


def test_absolute_mesh_path(artifact):
    err = load_error(artifact({"robot.xml": mesh_xml("/etc/passwd")}))
    assert isinstance(err, UnsafeArtifact)
    assert (err.code, err.path, err.element, err.line) == ("artifact.path_absolute", "robot.xml", "mesh", 3)
    assert str(err) == (
        "robot.xml:3 <mesh>: file '/etc/passwd' is absolute; references must be relative to the artifact directory"
    )


def test_dotdot_escape(artifact):
    err = load_error(artifact({"robot.xml": mesh_xml("../x.stl")}))
    assert err.code == "artifact.path_escape"
    assert str(err) == "robot.xml:3 <mesh>: file '../x.stl' resolves outside the artifact directory"


def test_dotdot_inside_stays_allowed(artifact):
    root = artifact({"robot.xml": mesh_xml("meshes/../meshes/b.stl"), "meshes/b.stl": STL})
    assert load_design(root).files == ("robot.xml", "meshes/b.stl")


def test_meshdir_escape_is_caught_through_the_combined_path(artifact):
    xml = mesh_xml("x.stl").replace("<mujoco>", '<mujoco><compiler meshdir="../elsewhere"/>')
    err = load_error(artifact({"robot.xml": xml}))
    assert err.code == "artifact.path_escape" and "'x.stl'" in str(err)


def test_symlink_out_of_the_directory(artifact):
    root = artifact({"robot.xml": mesh_xml("evil.stl")})
    os.symlink("/etc/passwd", root / "evil.stl")
    err = load_error(root)
    assert err.code == "artifact.symlink_escape"
    assert str(err) == (
        "robot.xml:3 <mesh>: file 'evil.stl' goes through symlink 'evil.stl' pointing outside the artifact directory"
    )


def test_symlinked_directory_out_of_the_directory(artifact):
    root = artifact({"robot.xml": mesh_xml("sub/passwd")})
    os.symlink("/etc", root / "sub")
    err = load_error(root)
    assert err.code == "artifact.symlink_escape" and "symlink 'sub'" in str(err)


def test_symlink_inside_the_directory_is_fine(artifact):
    root = artifact({"robot.xml": mesh_xml("alias.stl"), "meshes/b.stl": STL})
    os.symlink("meshes/b.stl", root / "alias.stl")
    assert load_design(root).files == ("robot.xml", "meshes/b.stl")


def test_include_outside(artifact, tmp_path):
    (tmp_path / "outside.xml").write_text("<mujoco/>")
    root = artifact({"robot.xml": '<mujoco>\n  <include file="../outside.xml"/>\n</mujoco>'})
    err = load_error(root)
    assert (err.code, err.element, err.line) == ("artifact.path_escape", "include", 2)
    assert str(err) == "robot.xml:2 <include>: file '../outside.xml' resolves outside the artifact directory"


def test_nested_include_escape_names_the_included_file(artifact):
    root = artifact(
        {
            "robot.xml": '<mujoco><include file="parts/a.xml"/></mujoco>',
            "parts/a.xml": '<mujoco>\n\n<include file="/etc/hosts"/></mujoco>',
        }
    )
    err = load_error(root)
    assert (err.code, err.path, err.line) == ("artifact.path_absolute", "parts/a.xml", 3)


def test_billion_laughs(artifact):
    levels = "".join(f'<!ENTITY lol{i} "{f"&lol{i - 1};" * 10}">' for i in range(1, 10))
    bomb = f'<?xml version="1.0"?>\n<!DOCTYPE lolz [<!ENTITY lol0 "lol">{levels}]>\n<mujoco model="&lol9;"/>'
    err = load_error(artifact({"robot.xml": bomb}))
    assert err.code == "mjcf.entity"
    assert str(err) == (
        "robot.xml: DOCTYPE/ENTITY declarations are not allowed in MJCF (entity expansion is disabled)"
    )


def test_external_entity_in_utf16_is_refused(artifact):
    xxe = '<!DOCTYPE m [<!ENTITY x SYSTEM "file:///etc/passwd">]><mujoco model="&x;"/>'
    err = load_error(artifact({"robot.xml": xxe.encode("utf-16")}))
    assert err.code == "mjcf.entity"


def test_200_mb_mesh_is_refused_before_reading(artifact):
    root = artifact({"robot.xml": mesh_xml("big.stl"), "big.stl": b""})
    os.truncate(root / "big.stl", 200 * 2**20)  # sparse: nothing is written
    err = load_error(root)
    assert err.code == "artifact.too_large"
    assert str(err) == "robot.xml:3 <mesh>: file 'big.stl' has 209715200 bytes, limit 67108864"


def test_total_bytes_limit(artifact):
    root = artifact({"robot.xml": mesh_xml("b.stl"), "b.stl": STL})
    err = load_error(root, LoadLimits(max_total_bytes=len(STL)))
    assert err.code == "artifact.too_large" and "files read" in str(err)


def test_truncated_xml(artifact):
    err = load_error(artifact({"robot.xml": "<mujoco>\n  <worldbody>\n    <body name='a'>"}))
    assert (err.code, err.line) == ("mjcf.parse", 3)
    assert (
        str(err)
        == "robot.xml:3: XML parse error at line 3, column 20: Premature end of data in tag body line 3"
    )


def test_invalid_utf8(artifact):
    err = load_error(
        artifact({"robot.xml": b"<mujoco>\n<worldbody><body name='\xff\xfe'/></worldbody></mujoco>"})
    )
    assert (err.code, err.line) == ("mjcf.parse", 2)
    assert (
        str(err) == "robot.xml:2: XML parse error at line 2, column 24: Invalid bytes in character encoding"
    )


def test_empty_file(artifact):
    err = load_error(artifact({"robot.xml": ""}))
    assert err.code == "mjcf.parse" and "Document is empty" in str(err)


def test_zip_renamed_stl(artifact):
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as zf:
        zf.writestr("payload.txt", "hello " * 100)
    err = load_error(artifact({"robot.xml": mesh_xml("part.stl"), "part.stl": buf.getvalue()}))
    assert (err.code, err.element, err.line) == ("mesh.invalid", "mesh", 3)
    # bytes 80..84 (the STL face count) fall inside the stored text "hello hello ..."
    assert str(err) == (
        "robot.xml:3 <mesh>: file 'part.stl': not a valid binary STL: 720 bytes, but the header claims "
        "1746956140 faces (84 + 50 x 1746956140 = 87347807084 bytes) (its bytes look like a ZIP archive)"
    )


def test_binary_in_obj(artifact):
    err = load_error(artifact({"robot.xml": mesh_xml("part.obj"), "part.obj": b"v 0 0 0\x00\x01"}))
    assert err.code == "mesh.invalid" and "binary data in a text format" in str(err)


def test_too_many_faces_from_the_stl_header(artifact):
    err = load_error(artifact({"robot.xml": mesh_xml("b.stl"), "b.stl": STL}), LoadLimits(max_mesh_faces=11))
    assert err.code == "mesh.too_many_faces"
    assert str(err) == "robot.xml:3 <mesh>: file 'b.stl': mesh has 12 faces, limit 11"


def test_unsupported_mesh_format(artifact):
    err = load_error(artifact({"robot.xml": mesh_xml("b.ply"), "b.ply": b"ply\n"}))
    assert err.code == "mesh.invalid"
    assert str(err).endswith("unsupported mesh format '.ply'; supported: .msh, .obj, .stl")


def test_png_bomb_dimensions(artifact):
    png = (
        b"\x89PNG\r\n\x1a\n"
        + b"\x00\x00\x00\x0dIHDR"
        + (100000).to_bytes(4, "big") * 2
        + b"\x08\x02\x00\x00\x00"
    )
    xml = '<mujoco>\n<asset>\n<texture name="t" type="2d" file="t.png"/>\n</asset>\n</mujoco>'
    err = load_error(artifact({"robot.xml": xml, "t.png": png}))
    assert (err.code, err.element, err.line) == ("artifact.too_large", "texture", 3)
    assert str(err).endswith("PNG is 100000 x 100000 = 10000000000 pixels, limit 16777216")


def test_deep_nesting_beyond_libxml(artifact):
    xml = "<mujoco><worldbody>" + "<body>" * 300 + "</body>" * 300 + "</worldbody></mujoco>"
    err = load_error(artifact({"robot.xml": xml}))
    assert err.code == "mjcf.too_deep" and "Excessive depth" in str(err)


def test_deep_nesting_beyond_our_limit(artifact):
    xml = "<mujoco><worldbody>\n" + "<body>\n" * 80 + "</body>" * 80 + "</worldbody></mujoco>"
    err = load_error(artifact({"robot.xml": xml}))
    # <mujoco> is depth 1, <worldbody> 2, body k is depth k + 2 on line k + 1: body 63 is the first too deep
    assert (err.code, err.element, err.line) == ("mjcf.too_deep", "body", 64)
    assert str(err) == "robot.xml:64 <body>: element nesting exceeds 64 levels"


def test_element_count_limit(artifact):
    xml = "<mujoco><worldbody>" + "<site/>" * 50 + "</worldbody></mujoco>"
    err = load_error(artifact({"robot.xml": xml}), LoadLimits(max_elements=20))
    assert err.code == "mjcf.too_large" and "more than 20 elements" in str(err)


def test_50_mb_attribute(artifact):
    root = artifact({"robot.xml": b'<mujoco model="' + b"a" * (50 * 2**20) + b'"/>'})
    err = load_error(root)  # the file itself is over the XML size limit
    assert err.code == "artifact.too_large"
    assert str(err) == "robot.xml: file 'robot.xml' has 52428818 bytes, limit 8388608"
    err = load_error(root, LoadLimits(max_xml_bytes=64 * 2**20))  # then libxml2's own buffer limit
    assert err.code == "mjcf.too_large" and "Resource limit exceeded" in str(err)


def test_long_attribute_under_libxml_limit(artifact):
    err = load_error(artifact({"robot.xml": '<mujoco model="' + "a" * 2_000_000 + '"/>'}))
    assert (err.code, err.element) == ("mjcf.too_large", "mujoco")
    assert str(err) == "robot.xml:1 <mujoco>: attribute 'model' has 2000000 characters, limit 1000000"


def test_valid_xml_that_is_not_mjcf(artifact):
    err = load_error(
        artifact({"robot.xml": '<?xml version="1.0"?>\n<robot name="r"><link name="a"/></robot>'})
    )
    assert (err.code, err.element, err.line) == ("mjcf.not_mjcf", "robot", 2)
    assert str(err) == "robot.xml:2 <robot>: root element is <robot>, expected <mujoco>: not an MJCF file"


def test_included_file_that_is_not_mjcf(artifact):
    root = artifact({"robot.xml": '<mujoco><include file="a.xml"/></mujoco>', "a.xml": "<robot/>"})
    err = load_error(root)
    assert (err.code, err.path) == ("mjcf.not_mjcf", "a.xml")


def test_missing_file_and_entry(artifact):
    err = load_error(artifact({"robot.xml": mesh_xml("nope.stl")}))
    assert err.code == "artifact.missing_file"
    assert str(err) == "robot.xml:3 <mesh>: file 'nope.stl' (looked for 'nope.stl') does not exist"
    with pytest.raises(RleError) as info:
        load_design(artifact({"other.xml": "<mujoco/>"}, name="b"), "robot.xml")
    assert info.value.code == "artifact.missing_file"


def test_fifo_is_not_read(artifact):
    root = artifact({"robot.xml": mesh_xml("pipe.stl")})
    os.mkfifo(root / "pipe.stl")
    assert load_error(root).code == "artifact.not_a_file"


def test_repeated_include(artifact):
    xml = '<mujoco>\n<include file="a.xml"/>\n<include file="a.xml"/>\n</mujoco>'
    err = load_error(artifact({"robot.xml": xml, "a.xml": "<mujoco/>"}))
    assert (err.code, err.line) == ("mjcf.include_repeat", 3)


def test_include_chain_depth_and_file_count(artifact):
    files = {f"i{k}.xml": f'<mujoco><include file="i{k + 1}.xml"/></mujoco>' for k in range(30)}
    files["i30.xml"] = "<mujoco/>"
    root = artifact({"robot.xml": '<mujoco><include file="i0.xml"/></mujoco>', **files})
    err = load_error(root)
    # robot.xml includes i0 (depth 1) ... i15 includes i16 at depth 17
    assert (err.code, err.path, err.element) == ("mjcf.too_deep", "i15.xml", "include")
    assert str(err) == "i15.xml:1 <include>: includes nested deeper than 16 files"
    err = load_error(root, LoadLimits(max_files=5, max_include_depth=100))
    assert (err.code, str(err)) == ("artifact.too_large", "i3.xml:1 <include>: more than 5 files")


def test_include_cycle(artifact):
    root = artifact(
        {
            "robot.xml": '<mujoco><include file="a.xml"/></mujoco>',
            "a.xml": '<mujoco><include file="robot.xml"/></mujoco>',
        }
    )
    err = load_error(root)
    assert (err.code, err.path) == ("mjcf.include_repeat", "a.xml")


@pytest.mark.parametrize(
    ("xml", "tag"),
    [
        ('<mujoco>\n<extension><plugin plugin="mujoco.pid"/></extension>\n</mujoco>', "extension"),
        ('<mujoco>\n<worldbody><body><plugin plugin="x"/></body></worldbody></mujoco>', "plugin"),
    ],
)
def test_plugins_are_forbidden(artifact, xml, tag):
    err = load_error(artifact({"robot.xml": xml}))
    assert (err.code, err.element) == ("mjcf.forbidden_element", tag)
    assert str(err).endswith(f"<{tag}> is not allowed: engine plugins run native code")


def test_submodel_asset_is_forbidden_after_path_check(artifact):
    xml = '<mujoco>\n<asset>\n<model name="s" file="{}"/>\n</asset>\n</mujoco>'
    err = load_error(artifact({"robot.xml": xml.format("../s.xml")}))
    assert err.code == "artifact.path_escape"
    err = load_error(artifact({"robot.xml": xml.format("s.xml"), "s.xml": "<mujoco/>"}, name="b"))
    assert (err.code, err.element, err.line) == ("mjcf.forbidden_element", "model", 3)


def test_cube_texture_faces_are_checked(artifact):
    xml = '<mujoco>\n<asset>\n<texture name="sky" type="skybox" fileright="../r.png"/>\n</asset>\n</mujoco>'
    err = load_error(artifact({"robot.xml": xml}))
    assert (err.code, err.element, err.line) == ("artifact.path_escape", "texture", 3)


def test_absolute_meshdir(artifact):
    xml = mesh_xml("b.stl").replace("<mujoco>", '<mujoco><compiler meshdir="/usr/share"/>')
    err = load_error(artifact({"robot.xml": xml, "b.stl": STL}))
    assert (err.code, err.element) == ("artifact.path_absolute", "compiler")


def test_errors_are_mjcf_errors():
    assert issubclass(UnsafeArtifact, MjcfError) and issubclass(MjcfError, RleError)
