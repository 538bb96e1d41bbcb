"""The world light in the viewport's sync (issue 47): an edit of the world (its strength,
its image's pixels, another image) builds only the world light's map again, not the
top-level BVH; an edit of a material or an object's transform keeps the map; and after
each the synced scene renders the pixels of a full export, bit for bit
(tests/blender/test_sync.py's rule)."""

import bpy
import numpy as np
import pytest
from test_sync import LiveSync, full_export, render
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


def test_a_viewport_job_is_lit_by_the_world_and_sees_a_world_edit(native, scene, live):
    # The viewport's RenderJob reads the synced scene: the floor, lit by nothing but the
    # world, is brighter after the world's strength is doubled (and twice as bright:
    # the same draws, the same map's shape).
    before = render(native, live.sync, scene)
    live.edit(lambda: _strength(scene, 2.0))
    after = render(native, live.sync, scene)
    floor = (slice(0, 6), slice(24, 40))
    assert before[floor][..., :3].mean() > 0.01
    np.testing.assert_allclose(after[floor][..., :3], 2.0 * before[floor][..., :3], rtol=1e-4)
