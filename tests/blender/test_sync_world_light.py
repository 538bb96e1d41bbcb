"""The world light in the viewport's sync (issue 47): an edit of the world (its strength,
its image's pixels, another image) builds only the world light's map again, not the
top-level BVH; an edit of a material or an object's transform keeps the map; and after
each the synced scene renders the pixels of a full export, bit for bit
(tests/blender/test_sync.py's rule)."""

import bpy
import numpy as np
import pytest
from test_sync import LiveSync, full_export, render
from whitted.export.camera import convert_camera
from whitted.properties.presets import preset
from whitted.sync.native_data import native_camera
from whitted_tools.material_scenes import lambert_material, numpy_image
from whitted_tools.world_scenes import lit_by


def _sky(width, height, sun):
    """float32[height, width, 4]: a dim blue sky brighter overhead, one bright texel
    block at `sun` (column, row from the bottom)."""
    rows = np.linspace(0.0, 1.0, height, dtype=np.float32)[:, None, None]
    pixels = np.broadcast_to(
        np.float32([0.05, 0.1, 0.2, 1.0]) * (0.2 + rows), (height, width, 4)
    ).copy()
    pixels[..., 3] = 1.0
    x, y = sun
    pixels[y : y + 2, x : x + 2, :3] = 40.0
    return pixels


@pytest.fixture
def scene(empty_scene):
    image = numpy_image("Sky", _sky(32, 16, (6, 11)))
    lit_by(empty_scene, image, lambert_material("Ball", 0.8), size=(64, 48))
    bpy.context.view_layer.update()
    return empty_scene


@pytest.fixture
def live(native, scene):
    live = LiveSync(native, scene)
    yield live
    live.close()


def _strength(scene, value):
    scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = value


def _repaint(image, sun):
    image.pixels.foreach_set(_sky(32, 16, sun).reshape(-1))
    image.update_tag()  # as texture painting does: the depsgraph hears of it then


def _other_image(scene):
    texture = scene.world.node_tree.nodes["Environment Texture"]
    texture.image = numpy_image("Dawn", _sky(32, 16, (20, 9)))


def _base_color(name, color):
    diffuse = bpy.data.materials[name].node_tree.nodes["Diffuse BSDF"]
    diffuse.inputs["Color"].default_value = color


# (name, edit(scene), whether it builds the world light again)
EDITS = (
    ("world strength", lambda s: _strength(s, 2.5), True),
    ("world image pixels", lambda s: _repaint(bpy.data.images["Sky"], (24, 12)), True),
    ("world image swapped", _other_image, True),
    ("material colour", lambda s: _base_color("Ball", (0.2, 0.7, 0.3, 1.0)), False),
    ("object moved", lambda s: setattr(s.objects["Ball"], "location", (0.6, 0.3, 1.1)), False),
    ("object rotated", lambda s: setattr(s.objects["Floor"], "rotation_euler", (0, 0, 0.4)), False),
)


def test_a_world_edit_builds_only_the_map_and_other_edits_keep_it(native, scene, live):
    synced = live.sync.scene
    assert render(native, live.sync, scene).any()
    assert synced.world_light["on"] and synced.world_light["map"] == (32, 16)
    for name, change, rebuilds in EDITS:
        maps, top_levels = synced.world_light_builds, synced.top_level_builds
        reports = live.edit(lambda change=change: change(scene))
        assert reports, f"{name}: no depsgraph update reached the sync"
        synced_pixels = render(native, live.sync, scene)
        assert synced.world_light_builds == maps + rebuilds, name
        if rebuilds:
            # The world, or the image it reads, exported again; no geometry: the same
            # top-level BVH.
            assert any(report.world or report.textures for report in reports), name
            assert synced.top_level_builds == top_levels, name
            assert not any(report.meshes or report.instances for report in reports), name
        full = full_export(native, scene)
        expected = render(native, full, scene)
        assert np.array_equal(synced_pixels, expected), (
            f"after '{name}': {np.count_nonzero((synced_pixels != expected).any(axis=-1))} "
            f"pixels differ, max {np.abs(synced_pixels - expected).max()}"
        )


def _viewport_render(native, scene_sync, blender_scene):
    """The synced scene as the viewport renders it (viewport.session's _start): its
    preset's quality, progressive; (image, stats) once every pass is done."""
    from whitted.export.film import convert_film
    from whitted.settings import native_settings

    width, height = blender_scene.render.resolution_x, blender_scene.render.resolution_y
    film = convert_film(blender_scene, width, height, region=(0, 0, width, height))
    quality = preset(blender_scene.whitted.viewport_preset)
    settings = native_settings(native, blender_scene, width, height, film, quality)
    settings.progressive = True
    camera = convert_camera(blender_scene.camera, blender_scene.render, [])
    job = native.RenderJob(scene_sync.scene, settings, camera=native_camera(native, camera))
    job.start()
    while not job.wait(1.0):
        pass
    return job.image(), job.stats()


def test_the_viewport_is_lit_by_the_world_and_a_world_edit_relights_it(native, scene, live):
    # The viewport's progressive job at its preset reads the synced scene: the floor, lit
    # by nothing but the world, is twice as bright once the world's strength is doubled
    # (the map's shape is the same; the preset's noise threshold takes other samples
    # where the relative noise differs, so the mean, not each pixel).
    before, stats = _viewport_render(native, live.sync, scene)
    world = next(e for e in stats["effects"] if e["name"] == "world light")
    assert world["on"] and stats["world_feelers"] > 0
    live.edit(lambda: _strength(scene, 2.0))
    after, _ = _viewport_render(native, live.sync, scene)
    floor = (slice(0, 6), slice(24, 40))
    lit = before[floor][..., :3].mean()
    assert lit > 0.01
    ratio = after[floor][..., :3].mean() / lit
    print(f"the floor after the world's strength doubled: {ratio:.4f} x")
    assert abs(ratio - 2.0) < 0.05
