"""Quality controls (issue 5): presets, their plumbing into the native settings,
the soft-shadow default and the texture filter override
(the Estimate operator: test_estimate.py)."""

import itertools
import json

import bpy
import pytest
from exported import exported_lights
from whitted.export.film import convert_film
from whitted.export.texture import ImageTextureSpec, convert_textures
from whitted.properties.presets import (
    PRESETS,
    Quality,
    apply_quality,
    matching_preset,
    preset,
    quality_of,
)
from whitted.settings import native_settings

WIDTH, HEIGHT = 48, 36


@pytest.fixture
def demo(empty_scene, demo_scene_module):
    scene = demo_scene_module.build_demo_scene(empty_scene)
    scene.render.resolution_x, scene.render.resolution_y = WIDTH, HEIGHT
    scene.render.resolution_percentage = 100
    return scene


def test_presets_are_ordered_and_stated():
    assert [key for key, _, _, _ in PRESETS] == ["DRAFT", "PREVIEW", "FINAL", "REFERENCE"]
    for _, label, description, values in PRESETS:
        assert label and description
        assert isinstance(values, Quality)
    # Each step up traces at least as deep and cuts off no more.
    qualities = [values for _, _, _, values in PRESETS]
    for cheaper, dearer in itertools.pairwise(qualities):
        assert cheaper.max_depth <= dearer.max_depth
        assert cheaper.cutoff >= dearer.cutoff
        assert cheaper.light_samples <= dearer.light_samples
        assert cheaper.glossy_samples <= dearer.glossy_samples
        assert cheaper.emitter_samples <= dearer.emitter_samples


@pytest.mark.parametrize("key", [key for key, _, _, _ in PRESETS])
def test_apply_preset_operator_sets_every_control(empty_scene, key):
    empty_scene.render.engine = "WHITTED"
    assert matching_preset(empty_scene.whitted) is None  # the tests' SEED_QUALITY is custom
    assert bpy.ops.whitted.apply_preset(preset=key) == {"FINISHED"}
    assert matching_preset(empty_scene.whitted) == key
    values = quality_of(empty_scene.whitted)
    names = (
        "max_depth",
        "aa_mode",
        "aa_samples",
        "aa_depth",
        "light_samples",
        "glossy_samples",
        "emitter_samples",
    )
    for name in names:
        assert getattr(values, name) == getattr(preset(key), name)
    assert values.cutoff == pytest.approx(preset(key).cutoff)
    empty_scene.whitted.max_depth += 1
    assert matching_preset(empty_scene.whitted) is None


def test_native_settings_carry_every_quality_control(empty_scene, native):
    quality = Quality(
        max_depth=7,
        aa_mode="ADAPTIVE",
        aa_samples=3,
        aa_threshold=0.2,
        aa_depth=2,
        adaptive_sampling=True,
        noise_threshold=0.03,
        adaptive_min_samples=8,
        light_samples=5,
        glossy_samples=4,
        emitter_samples=3,
        fresnel="SCHLICK",
        cutoff=0.02,
        texture_filter="CLOSEST",
        volume_step_rate=0.5,
    )
    apply_quality(empty_scene.whitted, quality)
    empty_scene.whitted.pixel_filter_type = "GAUSSIAN"
    empty_scene.whitted.filter_width = 2.5
    film = convert_film(empty_scene, 40, 30)
    settings = native_settings(native, empty_scene, 40, 30, film)
    assert settings.max_depth == 7
    assert settings.aa_mode == native.AntiAliasing.ADAPTIVE
    assert settings.aa_samples == 3
    assert settings.aa_threshold == pytest.approx(0.2)
    assert settings.aa_depth == 2
    assert settings.adaptive_sampling
    assert settings.noise_threshold == pytest.approx(0.03)
    assert settings.volume_step_rate == pytest.approx(0.5)
    assert settings.adaptive_min_samples == 8
    assert settings.glossy_samples == 4
    assert settings.emitter_samples == 3
    assert settings.fresnel == native.Fresnel.SCHLICK
    assert settings.cutoff == pytest.approx(0.02)
    # Not a quality control but a look: glass casts a full shadow unless tinted.
    assert settings.glass_shadows == native.GlassShadows.OPAQUE
    empty_scene.whitted.glass_shadows = "TINTED"
    tinted = native_settings(native, empty_scene, 40, 30, film)
    assert tinted.glass_shadows == native.GlassShadows.TINTED
    # Nor is the film's pixel filter.
    assert settings.pixel_filter == native.PixelFilterType.GAUSSIAN
    assert settings.filter_width == pytest.approx(2.5)


def render_stats(scene, render_pixels):
    render_pixels(scene)
    return json.loads(scene.whitted.last_stats)


def test_adaptive_takes_between_4_and_the_most_samples_per_pixel(demo, render_pixels):
    demo.whitted.aa_mode = "ADAPTIVE"
    demo.whitted.aa_threshold = 0.1
    demo.whitted.aa_depth = 2
    stats = render_stats(demo, render_pixels)
    most = (2**2 + 1) ** 2
    # The sky splits nothing; the edges split: strictly between.
    assert 4.0 < stats["samples_per_pixel"] < most
    assert stats["samples"] == stats["rays"]["camera"]
    assert stats["pixels"] == WIDTH * HEIGHT


@pytest.mark.parametrize("mode", ["REGULAR", "JITTERED"])
def test_grid_modes_take_n_squared_samples(demo, render_pixels, mode):
    demo.whitted.aa_mode = mode
    demo.whitted.aa_samples = 3
    stats = render_stats(demo, render_pixels)
    assert stats["samples_per_pixel"] == 9.0
    assert stats["settings"]["aa_mode"] == mode


def test_lower_cutoff_and_depth_trace_more_rays(demo, render_pixels):
    demo.whitted.max_depth = 1
    demo.whitted.cutoff = 0.2
    shallow = render_stats(demo, render_pixels)
    assert shallow["depth_limited"] > 0
    assert shallow["cutoff_skipped"] > 0
    demo.whitted.max_depth = 8
    demo.whitted.cutoff = 0.0
    deep = render_stats(demo, render_pixels)
    assert deep["cutoff_skipped"] == 0
    assert deep["rays"]["total"] > shallow["rays"]["total"]


def test_scene_shadow_samples_are_the_default_of_sized_lights(empty_scene):
    for name, own in (("Default", 0), ("Own", 3)):
        light = bpy.data.lights.new(name, "AREA")
        light.whitted.samples = own
        empty_scene.collection.objects.link(bpy.data.objects.new(name, light))
    empty_scene.whitted.light_samples = 6
    depsgraph = bpy.context.evaluated_depsgraph_get()
    samples = {light.name: light.samples for light in exported_lights(depsgraph, [], 6)}
    assert samples == {"Default": 6, "Own": 3}


def test_closest_texture_filter_overrides_the_nodes(empty_scene, warnings):
    image = bpy.data.images.new("Texels", 2, 2)
    spec = ImageTextureSpec(image, "LINEAR", "REPEAT", "UV", "")
    (authored,) = convert_textures({"t": spec}, warnings, "AUTHORED").values()
    (closest,) = convert_textures({"t": spec}, warnings, "CLOSEST").values()
    assert authored.interpolation == "LINEAR"
    assert closest.interpolation == "CLOSEST"
