"""Panoramic cameras (issue 30): every panorama type Blender offers, read where that
Blender keeps it (3.x camera.cycles, 4.0+ the camera), traced through the projection
Cycles defines (native scene/panorama.h) and compared with Cycles pixel by pixel."""

import json
import math

import bpy
import numpy as np
import pytest
from whitted.export.camera import convert_camera, panorama_settings
from whitted_tools.cycles_scenes import effect_figures, render_rgba, set_cycles_direct_light
from whitted_tools.material_scenes import dark_stage, emission_material, smooth_sphere
from whitted_tools.metrics import subject_figures

# Six emitting balls on the axes around the camera, each its own colour, and two off
# the axes to tell left from right and up from down.
BALLS = (
    ("PlusX", (4.0, 0.0, 0.0), (1.0, 0.1, 0.1)),
    ("MinusX", (-4.0, 0.0, 0.0), (0.1, 1.0, 1.0)),
    ("PlusY", (0.0, 4.0, 0.0), (0.1, 1.0, 0.1)),
    ("MinusY", (0.0, -4.0, 0.0), (1.0, 0.1, 1.0)),
    ("PlusZ", (0.0, 0.0, 4.0), (0.1, 0.1, 1.0)),
    ("MinusZ", (0.0, 0.0, -4.0), (1.0, 1.0, 0.1)),
    ("Corner", (3.0, 2.0, 1.5), (1.0, 0.6, 0.1)),
    ("Low", (3.0, -1.0, -1.5), (0.4, 0.3, 1.0)),
)


def compass(scene, panorama_type, width=96, height=48):
    """A panoramic camera of `panorama_type` at the origin looking along +X (rotation
    90, 0, -90: the centre of an environment map), among the balls, on a black world."""
    dark_stage(scene, width, height)
    for name, location, colour in BALLS:
        smooth_sphere(name, location, 1.0, emission_material(name, 1.0, colour))
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.rotation_euler = (math.radians(90.0), 0.0, math.radians(-90.0))
    scene.collection.objects.link(camera)
    scene.camera = camera
    camera.data.type = "PANO"
    settings = panorama_settings(camera.data)
    settings.panorama_type = panorama_type
    return settings


def panorama_types():
    camera = bpy.data.cameras.new("Probe")
    try:
        items = panorama_settings(camera).bl_rna.properties["panorama_type"].enum_items
        return [item.identifier for item in items]
    finally:
        bpy.data.cameras.remove(camera)


# Whitted and Cycles both sample each pixel at its centre (one sample; Cycles' 0.01-pixel
# filter), so only the balls' outlines can differ. Measured on Blender 3.4 and bpy 5.2:
# SSIM 1.0000 and the ratio 1.0000 for every type (the same pixels but a few at the
# balls' outlines); the settings make each type see some balls.
SETTINGS = {
    "EQUIRECTANGULAR": {"latitude_min": -1.2, "latitude_max": 1.4, "longitude_min": -2.8},
    "EQUIANGULAR_CUBEMAP_FACE": {},
    "MIRRORBALL": {},
    "FISHEYE_EQUIDISTANT": {"fisheye_fov": math.radians(250.0)},
    "FISHEYE_EQUISOLID": {"fisheye_fov": math.radians(200.0), "fisheye_lens": 6.0},
    "FISHEYE_LENS_POLYNOMIAL": {},
    "CENTRAL_CYLINDRICAL": {},
}


@pytest.mark.parametrize("panorama_type", list(SETTINGS))
def test_each_panorama_type_as_cycles(empty_scene, tmp_path, panorama_type):
    if panorama_type not in panorama_types():
        pytest.skip(f"Blender {bpy.app.version_string} has no {panorama_type} camera")
    scene = empty_scene
    square = panorama_type not in ("EQUIRECTANGULAR", "CENTRAL_CYLINDRICAL")
    settings = compass(scene, panorama_type, *((64, 64) if square else (96, 48)))
    for name, value in SETTINGS[panorama_type].items():
        setattr(settings, name, value)
    set_cycles_direct_light(scene, samples=1)
    scene.whitted.aa_samples = 1
    cycles = render_rgba(scene, "CYCLES", str(tmp_path / "cycles.exr"))
    whitted = render_rgba(scene, "WHITTED", str(tmp_path / "whitted.exr"))
    value, ratio = subject_figures(whitted, cycles)
    # Outside a fisheye's circle both are opaque black: the balls' coverage is the colour.
    covered = cycles[..., :3].max(axis=-1) > 0.05
    agree = float(((whitted[..., :3].max(axis=-1) > 0.05) == covered).mean())
    print(f"\n{panorama_type}: SSIM {value:.4f}, ratio {ratio:.4f}, coverage agrees {agree:.4f}")
    assert covered.mean() > 0.02  # the camera sees balls
    assert value > 0.99 and agree > 0.99
    assert abs(ratio - 1.0) < 0.02


def test_the_panorama_is_read_where_blender_keeps_it(empty_scene):
    settings = compass(empty_scene, "FISHEYE_EQUISOLID", 80, 40)
    settings.fisheye_lens = 8.0
    settings.fisheye_fov = 3.0
    empty_scene.camera.data.sensor_width = 30.0
    empty_scene.camera.data.shift_x = 0.1
    depsgraph = bpy.context.evaluated_depsgraph_get()
    camera = convert_camera(depsgraph.scene.camera, depsgraph.scene.render, [])
    assert camera.projection == "PANORAMIC"
    assert camera.panorama.type == "FISHEYE_EQUISOLID"
    assert camera.panorama.fisheye_lens == pytest.approx(8.0)
    assert camera.panorama.fisheye_fov == pytest.approx(3.0)
    # The sensor width spans the longer side; the height follows the image's aspect.
    assert camera.panorama.sensor == pytest.approx((30.0, 15.0))
    assert camera.window == pytest.approx((0.1, 1.1, 0.0, 1.0))


@pytest.mark.parametrize("pitch", [0.0, 180.0])
def test_looking_straight_up_and_down_has_no_nan(empty_scene, tmp_path, pitch, monkeypatch):
    # The camera looking straight down (pitch 0) and up (180): the equirectangular map's
    # poles (its top and bottom rows, all pixels along one direction) lie along the
    # camera's up axis, and its centre along the view axis, where the lens's plane is
    # oriented by that very axis; nothing may come out NaN there.
    stats_path = tmp_path / "stats.json"
    monkeypatch.setenv("WHITTED_STATS", str(stats_path))
    compass(empty_scene, "EQUIRECTANGULAR", 64, 32)
    empty_scene.camera.rotation_euler = (math.radians(pitch), 0.0, 0.0)
    empty_scene.whitted.aa_samples = 4
    empty_scene.camera.data.dof.use_dof = True  # a lens across the poles' rays too
    empty_scene.camera.data.dof.aperture_fstop = 2.0
    image = render_rgba(empty_scene, "WHITTED", str(tmp_path / "pole.exr"))
    assert np.isfinite(image).all()
    stats = json.loads(stats_path.read_text())
    assert stats["nonfinite_samples"] == 0
    # The upper pole is a ball (+Y for pitch 0, -Y for 180): the top row sees it all round.
    assert (image[-1, :, 3] > 0.99).all()


@pytest.mark.parametrize("panorama_type", ["EQUIRECTANGULAR", "MIRRORBALL"])
def test_depth_of_field_on_a_panorama_as_cycles(empty_scene, tmp_path, panorama_type):
    # Cycles' thin lens on a panorama spans the plane across each ray (its projection's
    # +X orients it): a ball at 1.3 m blurs when the balls at 3 m are in focus.
    scene = empty_scene
    compass(scene, panorama_type, *((96, 48) if panorama_type == "EQUIRECTANGULAR" else (64, 64)))
    smooth_sphere("Near", (1.2, -0.5, 0.3), 0.3, emission_material("Near", 1.0, (1, 1, 1)))
    dof = scene.camera.data.dof
    dof.use_dof = True
    dof.focus_distance = 3.0  # the balls' near sides
    dof.aperture_fstop = 0.05  # 50 mm: a 0.5 m radius; the near ball spreads ~0.25 rad
    set_cycles_direct_light(scene, samples=256)
    scene.cycles.pixel_filter_type = "BOX"  # over the pixel, as Whitted's grid
    scene.cycles.filter_width = 1.0
    scene.whitted.aa_mode = "JITTERED"
    scene.whitted.aa_samples = 8
    cycles = render_rgba(scene, "CYCLES", str(tmp_path / "cycles.exr"))
    whitted = render_rgba(scene, "WHITTED", str(tmp_path / "whitted.exr"))
    dof.use_dof = False
    sharp = render_rgba(scene, "WHITTED", str(tmp_path / "sharp.exr"))
    (value, ratio), sharp_value, error, sharp_error = effect_figures(
        f"{panorama_type} with a lens", whitted, sharp, cycles
    )
    # Measured on Blender 3.4: SSIM 0.991 for both, the mean difference 0.0028 against
    # the sharp render's 0.0099 and 0.0092; what is left is both renders' noise (Cycles'
    # 256 samples, Whitted's 64), shrinking with more samples on either side.
    assert value > 0.98 and value > sharp_value + 0.03
    assert error < 0.4 * sharp_error
    assert abs(ratio - 1.0) < 0.02


def _window_material():
    # Emission of the Window texture coordinate: the hit's point in the camera's image.
    material = bpy.data.materials.new("Window")
    if bpy.app.version < (5, 0, 0):
        material.use_nodes = True
    nodes = material.node_tree.nodes
    nodes.clear()
    coordinates = nodes.new("ShaderNodeTexCoord")
    emission = nodes.new("ShaderNodeEmission")
    output = nodes.new("ShaderNodeOutputMaterial")
    links = material.node_tree.links
    links.new(coordinates.outputs["Window"], emission.inputs["Color"])
    links.new(emission.outputs["Emission"], output.inputs["Surface"])
    return material


@pytest.mark.parametrize("panorama_type", ["EQUIRECTANGULAR", "FISHEYE_EQUISOLID", "MIRRORBALL"])
def test_the_window_coordinate_of_a_panorama_as_cycles(empty_scene, tmp_path, panorama_type):
    # Each projection's inverse: the panorama's point of the hit, as Cycles gives it.
    scene = empty_scene
    settings = compass(
        scene, panorama_type, *((96, 48) if panorama_type == "EQUIRECTANGULAR" else (64, 64))
    )
    if panorama_type == "FISHEYE_EQUISOLID":
        settings.fisheye_fov = math.radians(200.0)
        settings.fisheye_lens = 6.0
    window = _window_material()
    for name, _, _ in BALLS:
        bpy.data.objects[name].data.materials[0] = window
    set_cycles_direct_light(scene, samples=1)
    scene.whitted.aa_samples = 1
    cycles = render_rgba(scene, "CYCLES", str(tmp_path / "cycles.exr"))
    whitted = render_rgba(scene, "WHITTED", str(tmp_path / "whitted.exr"))
    seen = cycles[..., :3].max(axis=-1) > 0.0
    difference = np.abs(whitted[..., :3] - cycles[..., :3])[seen]
    print(f"\n{panorama_type} Window: median difference {np.median(difference):.2e}")
    assert seen.mean() > 0.02
    assert np.median(difference) < 1e-3  # measured: 4e-8 to 6e-8 (float rounding), 3.4
