"""Offscreen RGB-D rendering on CPU: metric depth, projection against rendered pixels, lifecycle."""

import os

import mujoco
import numpy as np
import pytest

from rle_design.sensors import BACKGROUND, RenderError, RgbdSensor

pytestmark = pytest.mark.render

PLANE_XML = """
<mujoco>
  <visual><global offwidth="160" offheight="120"/></visual>
  <worldbody>
    <light pos="0 0 3"/>
    <geom name="floor" type="plane" size="5 5 0.1" rgba="0.5 0.5 0.5 1"/>
    <camera name="down" pos="0.1 -0.2 0.8375" fovy="55"/>
    <camera name="oblique" pos="0.2 -0.9 0.9" xyaxes="1 0 0 0 0.7 0.7" fovy="60"/>
  </worldbody>
</mujoco>
"""

SPHERE_XML = """
<mujoco>
  <visual><global offwidth="320" offheight="240"/></visual>
  <worldbody>
    <light pos="0 0 3"/>
    <geom name="floor" type="plane" size="5 5 0.1" rgba="0.5 0.5 0.5 1"/>
    <geom name="ball" type="sphere" size="0.025" pos="0.13 -0.08 0.2" rgba="1 0 0 1"/>
    <camera name="c" pos="0.05 0.02 1.5" euler="0.1 -0.15 0.3" fovy="50"/>
    <camera name="side" pos="0.9 0.4 0.6" xyaxes="-0.4 0.9 0 -0.3 -0.1 0.9" fovy="40"/>
  </worldbody>
</mujoco>
"""

SKY_XML = """
<mujoco>
  <visual><global offwidth="64" offheight="64"/></visual>
  <worldbody>
    <light pos="0 0 3"/>
    <geom name="box" type="box" size="0.05 0.05 0.05"/>
    <camera name="c" pos="0 0 1" fovy="45"/>
  </worldbody>
</mujoco>
"""


def _setup(xml):
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    return m, d


def test_plane_at_known_distance_gives_metric_depth():
    m, d = _setup(PLANE_XML)
    with RgbdSensor(m, "down", 160, 120) as sensor:
        frame = sensor.render(d)
    # Camera looking straight down from height h onto the z = 0 plane: planar depth = h everywhere.
    h = 0.8375
    assert frame.depth.dtype == np.float32 and frame.depth.shape == (120, 160)
    assert np.abs(frame.depth - h).max() < 1e-3
    assert frame.valid.all()
    assert frame.rgb.shape == (120, 160, 3) and frame.rgb.dtype == np.uint8


def test_oblique_view_backprojects_onto_the_plane():
    m, d = _setup(PLANE_XML)
    with RgbdSensor(m, "oblique", 160, 120) as sensor:
        frame = sensor.render(d)
    pts = frame.camera.backproject(frame.depth, mask=frame.valid)
    assert len(pts) > 0.5 * frame.valid.size
    # Every valid pixel sees the floor z = 0, so lifted points must lie on it (1 mm).
    assert np.abs(pts[:, 2]).max() < 1e-3
    # Planar depth varies with the view angle: z_cam = distance along the optical axis.
    assert frame.depth[frame.valid].max() - frame.depth[frame.valid].min() > 0.3


@pytest.mark.parametrize("camera", ["c", "side"])
def test_projection_matches_rendered_sphere_centroid(camera):
    m, d = _setup(SPHERE_XML)
    gid = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, "ball")
    with RgbdSensor(m, camera, 320, 240) as sensor:
        frame = sensor.render(d)
    mask = frame.geom_ids() == gid
    assert mask.sum() > 50
    v, u = np.nonzero(mask)
    (uv,) = frame.camera.project(d.geom_xpos[gid])
    z = frame.camera.to_camera(d.geom_xpos[gid])[0, 2]
    assert abs(u.mean() - uv[0]) < 0.5
    assert abs(v.mean() - uv[1]) < 0.5
    # Nearest sphere point is on the ray through the centre: depth there ~ z - r (planar, 3 mm slack).
    assert abs(frame.depth[mask].min() - (z - 0.025)) < 3e-3
    # Colour comes out in the same orientation: the red ball's pixels are red, the grey floor's not.
    red = frame.rgb[mask].astype(int)
    assert (red[:, 0] > red[:, 1] + 30).mean() > 0.9  # grazing-light rim pixels are dark
    floor = frame.rgb[frame.geom_ids() == 0].astype(int)
    assert np.median(np.abs(floor[:, 0] - floor[:, 1])) < 10
    # The floor (and, from the side, the sky) fills the rest; segmentation names each pixel's geom.
    assert {0, gid} <= set(np.unique(frame.geom_ids()).tolist()) <= {BACKGROUND, 0, gid}


def test_background_is_invalid_and_unsegmented():
    m, d = _setup(SKY_XML)
    with RgbdSensor(m, "c", 64, 64) as sensor:
        frame = sensor.render(d)
    seg = frame.segmentation
    assert seg.shape == (64, 64, 2) and seg.dtype == np.int32
    assert seg[0, 0, 0] == BACKGROUND and not frame.valid[0, 0]
    assert frame.geom_ids()[32, 32] == 0 and frame.valid[32, 32]
    # The box top is at z = 0.05, the camera at z = 1.
    assert frame.depth[32, 32] == pytest.approx(0.95, abs=1e-3)
    assert frame.depth[0, 0] == pytest.approx(sensor.far, rel=1e-3)


def test_no_segmentation_mode_still_masks_background():
    m, d = _setup(SKY_XML)
    with RgbdSensor(m, "c", 64, 64, segmentation=False) as sensor:
        frame = sensor.render(d)
    assert frame.segmentation is None
    assert not frame.valid[0, 0] and frame.valid[32, 32]
    with pytest.raises(RenderError, match="this frame has no segmentation"):
        frame.geom_ids()


def test_unknown_backend_is_refused(monkeypatch):
    from rle_design.sensors.gl import requested_backend

    monkeypatch.setenv("MUJOCO_GL", "glfw")
    with pytest.raises(RenderError) as exc:
        requested_backend()
    assert str(exc.value) == "MUJOCO_GL='glfw' cannot render offscreen here. Available backends: egl, osmesa"


def test_lifecycle_close_twice_and_render_after_close():
    m, d = _setup(SKY_XML)
    sensor = RgbdSensor(m, "c", 32, 32, fast=False)
    assert sensor.render(d).rgb.shape == (32, 32, 3)
    assert m.vis.quality.offsamples == 4  # the model is left as it was
    sensor.close()
    sensor.close()
    assert sensor.closed
    with pytest.raises(RenderError) as exc:
        sensor.render(d)
    assert str(exc.value) == "render() called on a closed RgbdSensor"
    assert exc.value.code == "render.closed"
    with RgbdSensor(m, "c", 32, 32) as s2:
        s2.render(d)
    assert s2.closed


def test_image_larger_than_framebuffer_is_refused():
    m, _ = _setup(SKY_XML)
    with pytest.raises(RenderError) as exc:
        RgbdSensor(m, "c", 128, 64)
    assert str(exc.value) == (
        "image 128x64 exceeds the offscreen framebuffer 64x64; "
        'add <visual><global offwidth="128" offheight="64"/></visual>'
    )


def test_default_backend_prefers_egl_and_falls_back_to_osmesa():
    import rle_design

    libs = {"EGL": "libEGL.so.1", "OSMesa": "libOSMesa.so.8"}
    assert rle_design._default_gl_backend(libs.get) == "egl"
    assert rle_design._default_gl_backend({"OSMesa": "libOSMesa.so.8"}.get) == "osmesa"
    assert rle_design._default_gl_backend({}.get) == "egl"


def _on_floor(body: str, light: str = "0 0 3"):
    """A 64 x 48 scene: a light above ``light`` [m] pointing down, a floor plane, then ``body``."""
    return _setup(f"""
    <mujoco>
      <visual><global offwidth="64" offheight="48"/></visual>
      <worldbody>
        <light pos="{light}" dir="0 0 -1"/>
        <geom type="plane" size="5 5 0.1" rgba="0.5 0.5 0.5 1"/>
        {body}
      </worldbody>
    </mujoco>""")


def test_frustum_culling_leaves_the_image_unchanged():
    """Geoms behind the camera or beside its view are left out of the scene; what it sees is identical."""
    model, data = _on_floor("""
        <geom name="seen" type="box" size="0.1 0.1 0.1" pos="1 0 0.1" rgba="0.8 0.2 0.2 1"/>
        <geom name="edge" type="sphere" size="0.3" pos="1 0.75 0.3" rgba="0.2 0.8 0.2 1"/>
        <geom name="behind" type="box" size="0.1 0.1 0.1" pos="-1 0 0.1"/>
        <geom name="aside" type="box" size="0.1 0.1 0.1" pos="0 3 0.1"/>
        <geom name="rod" type="box" size="1 0.02 0.02" pos="-0.5 0.8 0.1"/>
        <camera name="cam" pos="0 0 0.5" xyaxes="0 -1 0 0.3 0 1" fovy="60"/>""")
    with (
        RgbdSensor(model, "cam", 64, 48, cull=False) as full,
        RgbdSensor(model, "cam", 64, 48, cull=True) as culled,
    ):
        names = {model.geom(g).name for g in culled._outside(data)}
        assert names == {
            "behind",
            "aside",
            "rod",
        }  # the rod's bounding sphere reaches into the view, its box not
        a, b = full.render(data), culled.render(data)
    assert np.array_equal(a.rgb, b.rgb) and np.array_equal(a.depth, b.depth)
    assert np.array_equal(a.segmentation, b.segmentation)


def test_cameras_drawn_in_parallel_threads_give_the_arrays_of_one_after_the_other(monkeypatch):
    """``render_rgbd`` draws several cameras in parallel threads (each its own GL context): the same
    colour and depth as drawing them in turn and as ``RgbdSensor.render``; afterwards the contexts can
    be made current in the main thread again."""
    from rle_design.control import cameras

    model, data = _setup(SPHERE_XML)
    views = {}
    for parallel in (False, True):
        monkeypatch.setattr(cameras, "PARALLEL", "1" if parallel else "0")
        cameras.close_renderers()
        views[parallel] = [cameras.render_rgbd(model, data, ("c", "side"), (120, 160), 1) for _ in range(2)]
    if (os.cpu_count() or 1) > 1 and cameras._sensor(model, "c", (120, 160), 1).backend == "egl":
        assert cameras._POOL is not None
    again = cameras._sensor(model, "side", (120, 160), 1).render_rgbd(data)  # main thread, after the workers
    with RgbdSensor(model, "side", 160, 120, segmentation=False, sites=False, box_quads=1) as one:
        frame = one.render(data)
    for rgb, depth in views[False] + views[True]:
        for cam in ("c", "side"):
            assert np.array_equal(rgb[cam], views[False][0][0][cam])
            assert np.array_equal(depth[cam], views[False][0][1][cam])
            assert rgb[cam].flags.c_contiguous and depth[cam].dtype == np.float32
    assert np.array_equal(frame.rgb, views[True][0][0]["side"]) and np.array_equal(frame.depth, again[1])
    assert np.array_equal(frame.depth, views[True][0][1]["side"]) and np.array_equal(frame.rgb, again[0])
    cameras.close_renderers()


def test_one_quad_per_box_face_keeps_geometry_depth_and_segmentation():
    """``box_quads=1`` changes only the lighting across box faces: depth and segmentation are identical
    and the model's own setting is restored after the renderer is built."""
    model, data = _on_floor(
        """
        <geom name="counter" type="box" size="0.6 0.3 0.45" pos="1.2 0 0.45" rgba="0.8 0.8 0.7 1"/>
        <camera name="cam" pos="0 0 1.2" xyaxes="0 -1 0 0.6 0 1" fovy="60"/>""",
        light="0.3 0.2 1.5",
    )
    with (
        RgbdSensor(model, "cam", 64, 48) as fine,
        RgbdSensor(model, "cam", 64, 48, box_quads=1) as coarse,
    ):
        assert model.vis.quality.numquads == 4  # restored
        a, b = fine.render(data), coarse.render(data)
    assert np.allclose(a.depth, b.depth, rtol=1e-5, atol=1e-6)
    assert np.array_equal(a.segmentation, b.segmentation) and np.array_equal(a.valid, b.valid)
    assert np.abs(a.rgb.astype(int) - b.rgb.astype(int)).mean() < 20  # the same picture, other shading
    with pytest.raises(ValueError, match="box_quads"):
        RgbdSensor(model, "cam", 64, 48, box_quads=0)


def test_the_view_cache_keeps_the_most_recent_renderers_and_frees_the_rest():
    """``render_rgb`` keeps at most ``MAX_RENDERERS`` renderers, least recently used out first: a
    process that builds a new scene per episode does not grow without bound (each renderer holds a GL
    context with the scene uploaded)."""
    from rle_design.control import cameras

    cameras.close_renderers()
    models = [mujoco.MjModel.from_xml_string(PLANE_XML) for _ in range(cameras.MAX_RENDERERS)]
    first = mujoco.MjData(models[0])
    mujoco.mj_forward(models[0], first)
    image = cameras.render_rgb(models[0], first, ("down", "oblique"), (24, 32))["down"]
    assert image.shape == (24, 32, 3) and len(cameras._SENSORS) == 2
    evicted = cameras._sensor(models[0], "down", (24, 32))
    for m in models[1:]:
        d = mujoco.MjData(m)
        mujoco.mj_forward(m, d)
        cameras.render_rgb(m, d, ("down",), (24, 32))
        cameras.render_rgb(models[0], first, ("oblique",), (24, 32))  # used again: stays
    assert len(cameras._SENSORS) == cameras.MAX_RENDERERS
    assert evicted.closed and not cameras._sensor(models[0], "oblique", (24, 32)).closed
    again = cameras.render_rgb(models[0], first, ("down",), (24, 32))["down"]
    np.testing.assert_array_equal(again, image)  # rebuilt on demand, same picture
    cameras.close_renderers()
    assert not cameras._SENSORS
