"""pytest inside Blender: the add-on enabled and an empty scene before each test."""

import bpy
import pytest
from whitted_tools import demo_scene
from whitted_tools.blender import ADDON, addon_problem, seed_quality
from whitted_tools.render import render_exr


def _enable_addon():
    problem = addon_problem()
    if problem:
        pytest.exit(f"Blender {bpy.app.version_string}: {problem}", returncode=4)


def pytest_configure(config):
    # Before test modules are collected: they import the add-on's modules.
    _enable_addon()


def pytest_report_header(config):
    return f"Blender {bpy.app.version_string}, add-on '{ADDON}' enabled"


@pytest.fixture(autouse=True)
def empty_scene():
    """A factory-fresh empty scene at whitted_tools.blender.SEED_QUALITY; resetting
    also disables add-ons, so re-enable."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    _enable_addon()
    seed_quality(bpy.context.scene)
    return bpy.context.scene


@pytest.fixture
def new_scene():
    """A factory-fresh empty scene with a new scene's own Whitted settings (the
    NEW_SCENE preset, denoising on)."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    _enable_addon()
    return bpy.context.scene


@pytest.fixture
def warnings():
    """The list an exporter appends its warnings to."""
    return []


@pytest.fixture(scope="session")
def demo_scene_module():
    """whitted_tools.demo_scene: build_demo_scene() and the figures tests read back."""
    return demo_scene


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
        return render_exr(scene, tmp_path / "render.exr", engine="WHITTED")

    return render
