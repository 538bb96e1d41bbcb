"""The add-on registers the Whitted engine, its settings and panels."""

import sys

import bpy
import pytest
import whitted
from whitted import native


def registered_engines():
    # Python keeps unregistered subclasses too; is_registered tells them apart. Some
    # built-in engines (HydraRenderEngine in 5.0) have no bl_idname.
    engines = bpy.types.RenderEngine.__subclasses__()
    return {getattr(e, "bl_idname", None) for e in engines if e.is_registered}


def test_engine_is_listed(empty_scene):
    assert "WHITTED" in registered_engines()
    empty_scene.render.engine = "WHITTED"  # refused unless the engine is registered
    assert empty_scene.render.engine == "WHITTED"


def test_engine_reads_shader_nodes():
    engine = whitted.engine.WhittedRenderEngine
    assert engine.bl_label == "Whitted"
    assert engine.bl_use_shading_nodes_custom is False
    assert engine.bl_use_preview is True  # material previews render with Whitted


def test_scene_settings_defaults(empty_scene):
    settings = empty_scene.whitted
    assert settings.max_depth == 5
    assert settings.aa_samples == 2
    assert settings.fresnel == "EXACT"
    assert settings.tile_size == 32
    assert settings.use_waves  # the recursive kernel is one setting away
    assert settings.ambient_strength == 1.0


def test_render_panel_polls_only_for_whitted(empty_scene):
    panel = bpy.types.WHITTED_RENDER_PT_sampling
    empty_scene.render.engine = "WHITTED"
    assert panel.poll(bpy.context)
    empty_scene.render.engine = "CYCLES"
    assert not panel.poll(bpy.context)


def test_blender_panels_shown_for_whitted():
    panels = [getattr(bpy.types, name, None) for name in whitted.COMPAT_PANELS]
    present = [panel for panel in panels if panel is not None]
    # The output dimensions, camera lens and light panels exist in every target version.
    for name in ("RENDER_PT_format", "DATA_PT_lens", "DATA_PT_context_light"):
        assert getattr(bpy.types, name) in present
    for panel in present:
        assert "WHITTED" in panel.COMPAT_ENGINES, panel.__name__


def test_unregister_removes_engine_and_panels():
    import addon_utils

    addon_utils.disable("whitted", default_set=True)
    try:
        assert "WHITTED" not in registered_engines()
        with pytest.raises(TypeError):
            bpy.context.scene.render.engine = "WHITTED"
        assert "WHITTED" not in bpy.types.RENDER_PT_format.COMPAT_ENGINES
        assert not hasattr(bpy.types.Scene, "whitted")
    finally:
        addon_utils.enable("whitted", default_set=True)


def test_missing_native_module_names_the_build_command(monkeypatch):
    # As if the module had never been built: importing it fails.
    monkeypatch.delattr(whitted, "whitted_native", raising=False)
    monkeypatch.setitem(sys.modules, "whitted.whitted_native", None)
    with pytest.raises(ImportError, match="whitted_native") as error:
        native.load_native()
    assert native.BUILD_COMMAND in str(error.value)


def test_render_without_native_module_reports_error(monkeypatch, empty_scene):
    monkeypatch.delattr(whitted, "whitted_native", raising=False)
    monkeypatch.setitem(sys.modules, "whitted.whitted_native", None)
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    empty_scene.collection.objects.link(camera)
    empty_scene.camera = camera
    empty_scene.render.engine = "WHITTED"
    empty_scene.render.resolution_x, empty_scene.render.resolution_y = 8, 8
    # An ERROR report from the engine makes the operator raise.
    with pytest.raises(RuntimeError, match="Build it from the repository root"):
        bpy.ops.render.render()


def test_tiles_are_clipped_to_the_render_region():
    clip = whitted.engine._clip_tiles
    region = (10, 20, 30, 25)  # xmin, ymin, xmax, ymax
    tiles = [(0, 0, 16, 16), (0, 16, 16, 16), (16, 16, 16, 16), (32, 16, 16, 16), (12, 21, 2, 2)]
    assert list(clip(tiles, region)) == [(10, 20, 6, 5), (16, 20, 14, 5), (12, 21, 2, 2)]


def test_finished_tiles_are_merged_into_few_rectangles():
    merge = whitted.engine._merge_tiles
    # Out of order, two rows, a gap (a tile still being traced), a shorter last row.
    tiles = [(32, 0, 32, 32), (0, 0, 32, 32), (96, 0, 32, 32), (0, 32, 32, 8), (32, 32, 32, 8)]
    assert merge(tiles) == [(0, 0, 64, 32), (96, 0, 32, 32), (0, 32, 64, 8)]
    # A whole image, 3 x 3 tiles in any order, is one rectangle.
    whole = [(x, y, 32, 32) for y in (64, 0, 32) for x in (32, 0, 64)]
    assert merge(whole) == [(0, 0, 96, 96)]
    assert merge([]) == []


def test_a_failing_worker_becomes_a_blender_report_not_a_crash(
    empty_scene, demo_scene_module, monkeypatch
):
    # The native test hook: the worker that takes tile 0 throws std::bad_alloc. The job
    # stops every worker and wait() raises MemoryError, which the engine reports.
    real_sync_frame = whitted.engine.sync_frame

    def failing(*args, **kwargs):
        frame = real_sync_frame(*args, **kwargs)
        frame.settings.fault_tile = 0
        return frame

    monkeypatch.setattr(whitted.engine, "sync_frame", failing)
    demo_scene_module.build_demo_scene(empty_scene)
    empty_scene.render.engine = "WHITTED"
    empty_scene.render.resolution_x, empty_scene.render.resolution_y = 96, 64
    # The engine's error report is what the render operator raises.
    with pytest.raises(RuntimeError, match="Whitted: the render failed: std::bad_alloc"):
        bpy.ops.render.render()
    # Blender is still here, and the next render works.
    monkeypatch.setattr(whitted.engine, "sync_frame", real_sync_frame)
    bpy.ops.render.render()
    assert json_stats(empty_scene)["pixels"] == 96 * 64


def json_stats(scene):
    import json

    return json.loads(scene.whitted.last_stats)
