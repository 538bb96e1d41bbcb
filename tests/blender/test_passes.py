"""Render passes (addon/result.py, docs/PASSES.md): which passes a view layer
enables, Blender's pass panels, and the multilayer EXR that holds them, read back
with the OpenEXR library (not through Blender or our own code)."""

import os
import subprocess

import bpy
import numpy as np
import pytest
from whitted import result
from whitted.ui import passes as passes_ui

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


def render_multilayer(scene, path):
    """F12 of `scene` saved as a 32-bit multilayer EXR at `path`; its channels."""
    scene.render.engine = "WHITTED"
    settings = scene.render.image_settings
    if hasattr(settings, "media_type"):
        settings.media_type = "MULTI_LAYER_IMAGE"  # Blender 5.0: needed for every pass
    settings.file_format = "OPEN_EXR_MULTILAYER"
    settings.color_depth = "32"
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
