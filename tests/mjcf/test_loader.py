"""Valid artifacts: includes, asset directories, names, line numbers and in-memory assets."""

import io
import shutil

import mujoco
import numpy as np
import pytest
import trimesh
from PIL import Image

from rle_design.errors import MjcfError
from rle_design.mjcf.loader import load_design

STL = trimesh.creation.box([0.1, 0.2, 0.3]).export(file_type="stl")
OBJ = trimesh.creation.box([0.1, 0.2, 0.3]).export(file_type="obj")


def png_bytes() -> bytes:
    buf = io.BytesIO()
    Image.fromarray(np.full((4, 4, 3), 128, dtype=np.uint8)).save(buf, format="PNG")
    return buf.getvalue()


ROBOT = """<mujoco model="bot">
  <compiler meshdir="meshes" texturedir="textures"/>
  <include file="parts/assets.xml"/>
  <worldbody>
    <body name="base">
      <geom name="shell" type="mesh" mesh="shell"/>
      <include file="parts/arm.xml"/>
    </body>
  </worldbody>
</mujoco>
"""
ASSETS = """<mujoco>
  <asset>
    <mesh file="shell.stl"/>
    <mesh name="cover" file="sub/cover.obj"/>
    <texture name="grid" type="2d" file="grid.png"/>
    <material name="mat" texture="grid"/>
    <hfield name="terrain" file="terrain.png" size="1 1 0.1 0.1"/>
  </asset>
</mujoco>
"""
ARM = """<mujoco>
  <body name="arm" pos="0 0 0.2">
    <joint name="shoulder" type="hinge"/>
    <geom name="cover_geom" type="mesh" mesh="cover" material="mat"/>
    <site name="tool_site"/>
  </body>
</mujoco>
"""


@pytest.fixture
def bot(artifact):
    return artifact(
        {
            "robot.xml": ROBOT,
            "parts/assets.xml": ASSETS,
            "parts/arm.xml": ARM,
            "meshes/shell.stl": STL,
            "meshes/sub/cover.obj": OBJ,
            "textures/grid.png": png_bytes(),
            "meshes/terrain.png": png_bytes(),  # height fields follow meshdir, as in MuJoCo
        }
    )


def test_includes_and_asset_dirs(bot):
    design = load_design(bot)
    assert design.files == (
        "robot.xml",
        "parts/assets.xml",
        "parts/arm.xml",
        "meshes/shell.stl",
        "meshes/sub/cover.obj",
        "textures/grid.png",
        "meshes/terrain.png",
    )
    model = design.compile()
    # default asset names (file stem) survive the rewrite to in-memory keys
    assert [model.mesh(i).name for i in range(model.nmesh)] == ["shell", "cover"]
    assert model.hfield("terrain").nrow[0] == 4
    # a 0.1 x 0.2 x 0.3 m box mesh at the default density 1000 kg/m^3: m = rho a b c = 6 kg per mesh
    # (STL stores float32 vertices, hence rel 1e-6)
    assert model.body("base").mass[0] == pytest.approx(6.0, rel=1e-6)
    assert model.body("arm").mass[0] == pytest.approx(6.0, rel=1e-6)
    assert "meshdir" not in design.xml and all(k.startswith("rle") for k in design.assets)


def test_line_of_and_where(bot):
    design = load_design(bot)
    assert design.line_of("body", "base") == 5
    assert design.line_of("site", "tool_site") == 5
    assert design.where(design.find("site", "tool_site")) == ("parts/arm.xml", 5)
    assert design.where(design.find("geom", "shell")) == ("robot.xml", 6)
    assert design.line_of("site", "nope") is None


def test_assets_come_from_memory_not_disk(bot):
    design = load_design(bot)
    shutil.rmtree(bot / "meshes")
    (bot / "robot.xml").write_text("<mujoco/>")
    model = design.fresh_spec().compile()
    assert model.nmesh == 2 and model.nbody == 3


def test_compile_error_names_the_included_file_and_line(artifact):
    root = artifact(
        {
            "robot.xml": '<mujoco>\n<worldbody>\n<include file="arm.xml"/>\n</worldbody>\n</mujoco>',
            "arm.xml": '<mujoco>\n<body name="a">\n<geom type="mesh" mesh="missing"/>\n</body>\n</mujoco>',
        }
    )
    design = load_design(root)
    with pytest.raises(MjcfError) as info:
        design.compile()
    err = info.value
    assert (err.code, err.path, err.line) == ("mjcf.compile", "arm.xml", 3)
    assert "mesh 'missing' not found" in str(err) and "line 3 of arm.xml" in str(err)


def test_schema_error_is_mapped_back(artifact):
    root = artifact({"robot.xml": '<mujoco>\n<worldbody>\n<geom sizee="1"/>\n</worldbody>\n</mujoco>'})
    with pytest.raises(MjcfError) as info:
        load_design(root)
    assert (info.value.code, info.value.path, info.value.line) == ("mjcf.schema", "robot.xml", 3)
    assert str(info.value) == (
        "robot.xml:3: MuJoCo parse error: XML Error: Schema violation: unrecognized attribute: 'sizee'\n"
        "Element 'geom', line 3 of robot.xml"
    )


def test_ascii_stl_is_refused_with_a_reason(artifact):
    ascii_stl = trimesh.creation.box([0.1, 0.1, 0.1]).export(file_type="stl_ascii").encode()
    xml = '<mujoco>\n<asset><mesh name="a" file="a.stl"/></asset></mujoco>'
    with pytest.raises(MjcfError) as info:
        load_design(artifact({"robot.xml": xml, "a.stl": ascii_stl}))
    assert info.value.code == "mesh.invalid"
    assert str(info.value) == (
        "robot.xml:2 <mesh>: file 'a.stl': ASCII STL is not supported by MuJoCo; save the mesh as binary STL"
    )


def test_msh_header_counts_are_checked(artifact):
    import struct

    verts = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype="<f4")
    faces = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], dtype="<i4")
    good = struct.pack("<4i", 4, 0, 0, 4) + verts.tobytes() + faces.tobytes()
    xml = '<mujoco><asset><mesh name="t" file="t.msh"/></asset><worldbody><geom type="mesh" mesh="t"/></worldbody></mujoco>'
    model = load_design(artifact({"robot.xml": xml, "t.msh": good})).compile()
    assert model.mesh_facenum[0] == 4
    bad = struct.pack("<4i", 4, 0, 0, 400) + verts.tobytes() + faces.tobytes()
    with pytest.raises(MjcfError) as info:
        load_design(artifact({"robot.xml": xml, "t.msh": bad}, name="bad"))
    assert info.value.code == "mesh.invalid"
    assert str(info.value).endswith(
        "not a valid MSH: header counts (4, 0, 0, 400) need 4864 bytes, file has 112"
    )


def test_stl_error_names_the_submitted_path_not_the_memory_key(artifact):
    # 200,001 faces pass our limit (2,000,000) but not MuJoCo's STL reader (200,000)
    stl = b"\0" * 80 + (200_001).to_bytes(4, "little") + b"\0" * (50 * 200_001)
    xml = '<mujoco><asset><mesh name="a" file="meshes/a.stl"/></asset><worldbody><geom type="mesh" mesh="a"/></worldbody></mujoco>'
    with pytest.raises(MjcfError) as info:
        load_design(artifact({"robot.xml": xml, "meshes/a.stl": stl})).compile()
    assert info.value.code == "mjcf.compile"
    assert "STL file 'meshes/a.stl'" in str(info.value) and "rle0" not in str(info.value)


@pytest.mark.parametrize("arm", ["panda", "xarm7"])
def test_canonical_arms_load_identically_through_memory(arm):
    from rle_design.scene import arm_model_path

    path = arm_model_path(arm)
    design = load_design(path.parent, path.name)
    model = design.compile()
    ref = mujoco.MjSpec.from_file(str(path)).compile()  # trusted asset: MuJoCo reads the disk itself
    assert (model.nbody, model.nmesh, model.ngeom) == (ref.nbody, ref.nmesh, ref.ngeom)
    assert np.array_equal(model.mesh_vert, ref.mesh_vert)
    assert np.allclose(model.body_mass, ref.body_mass, rtol=0, atol=1e-12)
    assert len(design.files) == 1 + model.nmesh + sum(1 for t in design.assets if t.endswith(".png"))


def test_loaded_design_composes_with_an_arm(artifact):
    from rle_design.scene import compile_spec, compose

    xml = """<mujoco><worldbody><body name="base" pos="0 0 0.2"><freejoint/>
    <geom type="box" size=".25 .2 .1" mass="38"/><site name="arm_mount_site" pos="0 0 0.1"/></body></worldbody></mujoco>"""
    design = load_design(artifact({"robot.xml": xml}))
    model = compile_spec(compose(design.spec, "xarm7", mount_site="arm_mount_site"))
    assert model.nu == 7 and model.body("base").mass[0] == 38.0


def test_cube_texture_from_six_files_in_texturedir(artifact):
    sides = ("right", "left", "up", "down", "front", "back")
    attrs = " ".join(f'file{s}="{s}.png"' for s in sides)
    xml = f'<mujoco><compiler texturedir="tex"/><asset><texture name="sky" type="skybox" {attrs}/></asset></mujoco>'
    root = artifact({"robot.xml": xml, **{f"tex/{s}.png": png_bytes() for s in sides}})
    design = load_design(root)
    assert design.files[1:] == tuple(f"tex/{s}.png" for s in sides)
    assert list(design.spec.textures[0].cubefiles) == [f"rle{i}/{s}.png" for i, s in enumerate(sides)]
    assert design.compile().ntex == 1
