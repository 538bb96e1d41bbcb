"""Render passes (addon/result.py, docs/PASSES.md): which passes a view layer
enables, Blender's pass panels, and the multilayer EXR that holds them, read back
with the OpenEXR library (not through Blender or our own code)."""

import os
import subprocess

import bpy
import numpy as np
import pytest
from whitted import result
from whitted.sync.frame import sync_frame
from whitted.ui import passes as passes_ui
from whitted_tools.material_scenes import lambert_material
from whitted_tools.render import enable_every_pass, use_multilayer_exr

REPO_ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
VENV_PYTHON = os.path.join(REPO_ROOT, ".venv", "bin", "python")

# Runs in .venv's CPython (where scripts/setup.sh installs OpenEXR): every channel of
# every layer of a multilayer EXR, saved as one .npz of name -> float32[h, w].
_READ_EXR = """
import sys
import numpy as np
import OpenEXR
with OpenEXR.File(sys.argv[1], separate_channels=True) as exr:
    # One part (Blender 3.4) or one part per pass (5.0); channels are named
    # "ViewLayer.Pass.X" in both.
    channels = {}
    for part in exr.parts:
        for name, c in part.channels.items():
            channels[name] = c.pixels.astype(np.float32)
    np.savez(sys.argv[2], **channels)
"""


def read_exr(path):
    """{channel name: float32[h, w]} of a multilayer EXR, rows top to bottom (as
    stored), read by the OpenEXR Python bindings in .venv's Python."""
    out = str(path) + ".npz"
    subprocess.run([VENV_PYTHON, "-c", _READ_EXR, str(path), out], check=True)
    with np.load(out) as data:
        return {name: data[name] for name in data.files}


def render_multilayer(scene, path, engine="WHITTED"):
    """F12 of `scene` by `engine` saved as a 32-bit multilayer EXR at `path`; its channels."""
    scene.render.engine = engine
    use_multilayer_exr(scene.render.image_settings)
    scene.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)
    return read_exr(path)


def layer_names(channels):
    """The pass names in EXR channel names ("ViewLayer.Combined.R" -> "Combined")."""
    return {name.split(".")[1] for name in channels}


@pytest.fixture
def small_scene(empty_scene):
    scene = empty_scene
    scene.render.resolution_x = 24
    scene.render.resolution_y = 16
    scene.render.resolution_percentage = 100
    bpy.ops.mesh.primitive_plane_add(size=4.0)
    # Diffuse in every Blender (5.0+ renders a mesh without a material as a Principled BSDF).
    bpy.context.object.data.materials.append(lambert_material("Lambert", 0.8))
    bpy.ops.object.camera_add(location=(0.0, 0.0, 3.0))
    scene.camera = bpy.context.object
    bpy.ops.object.light_add(type="POINT", location=(1.0, 1.0, 2.0))
    scene.whitted.aa_samples = 1
    return scene


def test_a_view_layer_enables_its_passes():
    view_layer = bpy.context.view_layer
    assert [spec.name for spec in result.enabled_passes(view_layer)] == [
        "Combined",
        result.COST_PASS,
    ]
    view_layer.whitted.use_pass_rays = False
    assert [spec.name for spec in result.enabled_passes(view_layer)] == ["Combined"]


def test_whitted_uses_blenders_pass_panels():
    bpy.context.scene.render.engine = "WHITTED"
    for name in ("VIEWLAYER_PT_layer", "VIEWLAYER_PT_layer_passes"):
        assert "WHITTED" in getattr(bpy.types, name).COMPAT_ENGINES
    panel = passes_ui.WHITTED_VIEWLAYER_PT_passes_whitted
    assert panel.bl_parent_id == "VIEWLAYER_PT_layer_passes"
    assert panel.poll(bpy.context)


def test_multilayer_exr_holds_the_enabled_passes(small_scene, tmp_path):
    channels = render_multilayer(small_scene, tmp_path / "passes.exr")
    assert layer_names(channels) == {"Combined", result.COST_PASS}
    rays = next(c for name, c in channels.items() if name.endswith(f"{result.COST_PASS}.X"))
    assert rays.shape == (16, 24)
    assert rays.min() >= 1.0  # every pixel traced its camera ray
    small_scene.view_layers[0].whitted.use_pass_rays = False
    channels = render_multilayer(small_scene, tmp_path / "combined.exr")
    assert layer_names(channels) == {"Combined"}


LIGHT_COMPONENTS = ("Diff", "Gloss", "Trans")


@pytest.fixture
def demo(empty_scene, demo_scene_module):
    scene = demo_scene_module.build_demo_scene(empty_scene)
    scene.render.resolution_x, scene.render.resolution_y = 48, 36
    scene.render.resolution_percentage = 100
    scene.whitted.aa_samples = 2
    return scene


def rgb(channels, name):
    """float32[h, w, 3] of pass `name` (its Blender 3.x name) in the EXR's channels
    ("ViewLayer.<name>.R", ...)."""
    name = result.blender_name(name)
    return np.stack([channels[f"ViewLayer.{name}.{c}"] for c in "RGB"], axis=-1)


def test_every_pass_is_in_the_exr_and_the_light_and_depth_passes_rebuild_combined(demo, tmp_path):
    view_layer = demo.view_layers[0]
    enable_every_pass(view_layer, result, contribution_depth=2)
    channels = render_multilayer(demo, tmp_path / "all.exr")
    expected = {spec.name for spec in result.enabled_passes(view_layer)}
    assert layer_names(channels) == expected
    assert {"Whitted Depth 0", "Whitted Depth 1", "Whitted Depth 2+"} <= expected
    combined = rgb(channels, "Combined")
    rebuilt = rgb(channels, "Emit") + rgb(channels, "Env")
    rebuilt += rgb(channels, "VolumeDir") + rgb(channels, "VolumeInd")  # 0: the demo has no fog
    for component in LIGHT_COMPONENTS:
        color = rgb(channels, f"{component}Col")
        rebuilt += color * (rgb(channels, f"{component}Dir") + rgb(channels, f"{component}Ind"))
    assert np.abs(rebuilt - combined).max() < 1e-4
    # The demo has all of them: lights, the sky as a light, a mirror, glass, the world.
    # DiffInd is the Lecture model's ambient term: the Blender model's sky is a light,
    # whose feelers are direct light (DiffDir), as Cycles' world light is.
    for name in ("DiffDir", "GlossDir", "GlossInd", "TransInd", "Env"):
        assert rgb(channels, name).max() > 0.0, name
    assert rgb(channels, "DiffInd").max() == 0.0
    depths = sum(
        rgb(channels, n) for n in ("Whitted Depth 0", "Whitted Depth 1", "Whitted Depth 2+")
    )
    assert np.abs(depths - combined).max() < 1e-4
    assert rgb(channels, "Whitted Depth 2+").max() > 0.0  # glass: light from deep in the tree
    cut = channels["ViewLayer.Whitted Cut Weight.X"]
    assert cut.min() == 0.0 and cut.max() <= 1.0
    # Lowering the maximum depth cuts more of each pixel's ray tree.
    demo.whitted.max_depth = 1
    shallow = render_multilayer(demo, tmp_path / "shallow.exr")
    assert shallow["ViewLayer.Whitted Cut Weight.X"].sum() > cut.sum()


def test_cut_weight_is_zero_when_nothing_is_cut(small_scene, tmp_path):
    view_layer = small_scene.view_layers[0]
    view_layer.whitted.use_pass_cut_weight = True
    channels = render_multilayer(small_scene, tmp_path / "diffuse.exr")
    assert np.all(channels["ViewLayer.Whitted Cut Weight.X"] == 0.0)


def data_scene(scene):
    """A floor, a cube and a smooth sphere with object and material pass indices,
    seen obliquely, for the data passes against Cycles."""
    scene.render.resolution_x, scene.render.resolution_y = 40, 30
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = False
    for name, add, location, index in (
        ("floor", lambda: bpy.ops.mesh.primitive_plane_add(size=8.0), (0, 0, 0), 2),
        ("cube", lambda: bpy.ops.mesh.primitive_cube_add(size=1.0), (-0.8, 0.2, 0.5), 5),
        ("ball", lambda: bpy.ops.mesh.primitive_uv_sphere_add(radius=0.6), (0.9, -0.2, 0.6), 9),
    ):
        add()
        obj = bpy.context.object
        obj.location = location
        obj.pass_index = index
        material = bpy.data.materials.new(name)
        material.use_nodes = True
        material.pass_index = index + 10
        obj.data.materials.append(material)
    bpy.ops.object.shade_smooth()  # the ball, selected last
    bpy.ops.object.camera_add(location=(3.5, -4.0, 3.0), rotation=(1.05, 0.0, 0.72))
    scene.camera = bpy.context.object
    bpy.ops.object.light_add(type="SUN")
    scene.world = bpy.data.worlds.new("mist")
    mist = scene.world.mist_settings
    mist.start, mist.depth, mist.falloff = 2.0, 9.0, "INVERSE_QUADRATIC"
    view_layer = scene.view_layers[0]
    for prop in (
        "use_pass_z",
        "use_pass_normal",
        "use_pass_position",
        "use_pass_uv",
        "use_pass_object_index",
        "use_pass_material_index",
        "use_pass_mist",
    ):
        setattr(view_layer, prop, True)
    scene.cycles.samples = 1
    scene.cycles.use_denoising = False
    scene.cycles.max_bounces = 0
    scene.cycles.filter_width = 0.01  # the camera ray through the pixel's centre, as ours
    scene.whitted.aa_samples = 1
    return scene


def test_data_passes_agree_with_cycles(empty_scene, tmp_path):
    scene = data_scene(empty_scene)
    ours = render_multilayer(scene, tmp_path / "whitted.exr")
    scene.render.engine = "CYCLES"
    bpy.ops.render.render(write_still=True)
    theirs = read_exr(tmp_path / "whitted.exr")

    def value(channels, name, ids):
        name = result.blender_name(name)
        return np.stack([channels[f"ViewLayer.{name}.{c}"] for c in ids], axis=-1)

    depth, cycles_depth = value(ours, "Depth", "Z"), value(theirs, "Depth", "Z")
    # Where both see a surface (the sky is 1e10 in both).
    both = (depth[..., 0] < 1e9) & (cycles_depth[..., 0] < 1e9)
    assert both.mean() > 0.8
    assert np.array_equal(depth[..., 0] < 1e9, cycles_depth[..., 0] < 1e9)
    np.testing.assert_allclose(depth[both], cycles_depth[both], rtol=1e-4)
    for name, ids, tolerance in (
        ("Position", "XYZ", 1e-4),
        ("Normal", "XYZ", 2e-3),
        ("UV", "UV", 1e-4),
        ("IndexOB", "X", 0.0),
        ("IndexMA", "X", 0.0),
        ("Mist", "Z", 1e-4),
    ):
        a, b = value(ours, name, ids)[both], value(theirs, name, ids)[both]
        close = np.abs(a - b).max(axis=-1) <= tolerance + 1e-4 * np.abs(b).max()
        # Normal: one pixel of the 1067 (on the smooth ball) differs by 0.07.
        assert close.mean() >= (0.995 if name == "Normal" else 1.0), (name, close.mean())


def test_the_viewport_can_show_every_pass(small_scene, native):
    """Each viewport display (scene.whitted.viewport_display) is a film pass the
    native job keeps when asked as the viewport asks, shown as RGBA."""
    keys = [
        item.identifier
        for item in small_scene.whitted.bl_rna.properties["viewport_display"].enum_items
    ]
    assert keys == [display.key for display in result.VIEWPORT_DISPLAYS]
    frame = sync_frame(bpy.context.evaluated_depsgraph_get(), native)
    for display in result.VIEWPORT_DISPLAYS:
        settings = frame.settings
        settings.passes = list(display.passes)
        settings.contribution_depth = result.MAX_CONTRIBUTION_DEPTH
        job = frame.job(native, settings)
        job.start()
        while not job.wait(1.0):
            pass
        pixels = job.display(display.kind, display.first)
        assert pixels.shape == (16, 24, 4) and np.isfinite(pixels).all(), display.key
