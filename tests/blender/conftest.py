"""pytest inside Blender: the add-on enabled and an empty scene before each test."""

import importlib.util
import os

import addon_utils
import bpy
import numpy as np
import pytest

ADDON = "whitted"
REPO_ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DEMO_SCENE_SCRIPT = os.path.join(REPO_ROOT, "scripts", "demo_scene.py")


def _enable_addon():
    if addon_utils.enable(ADDON, default_set=True) is None:
        pytest.exit(
            f"Blender {bpy.app.version_string} cannot enable the add-on '{ADDON}'. Install it "
            "with scripts/setup.sh (it links addon/ as ~/.config/blender/<version>/scripts/"
            f"addons/{ADDON}); addon_utils looked in: {addon_utils.paths()}",
            returncode=4,
        )


def pytest_configure(config):
    # Before test modules are collected: they import the add-on's modules.
    _enable_addon()


def pytest_report_header(config):
    return f"Blender {bpy.app.version_string}, add-on '{ADDON}' enabled"


@pytest.fixture(autouse=True)
def empty_scene():
    """A factory-fresh empty scene; resetting also disables add-ons, so re-enable."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    _enable_addon()
    return bpy.context.scene


@pytest.fixture
def warnings():
    """The list an exporter appends its warnings to."""
    return []


@pytest.fixture(scope="session")
def demo_scene_module():
    """scripts/demo_scene.py as a module (it is a script, not in a package)."""
    spec = importlib.util.spec_from_file_location("demo_scene", DEMO_SCENE_SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture
def native():
    """The compiled module; the render tests fail (not skip) without it."""
    from whitted.native import load_native

    try:
        return load_native()
    except ImportError as error:
        pytest.fail(str(error))


@pytest.fixture
def render_pixels(tmp_path, native):
    """A function that renders a scene with Whitted and returns its linear pixels.

    Blender 3.4 cannot read the Render Result's pixels from Python, so the
    render is written as a 32-bit float OpenEXR (linear: no view transform) and
    read back: float32[height, width, 4], rows bottom to top.
    """

    def render(scene):
        scene.render.engine = "WHITTED"
        image_settings = scene.render.image_settings
        image_settings.file_format = "OPEN_EXR"
        image_settings.color_depth = "32"
        image_settings.color_mode = "RGBA"
        scene.render.filepath = str(tmp_path / "render.exr")
        bpy.ops.render.render(write_still=True)
        image = bpy.data.images.load(scene.render.filepath)
        try:
            width, height = image.size
            pixels = np.empty(width * height * 4, dtype=np.float32)
            image.pixels.foreach_get(pixels)
        finally:
            bpy.data.images.remove(image)
        return pixels.reshape(height, width, 4)

    return render
