"""The add-on's controls and passes are built from the native tables (addon/native_tables.py):
every default and range of a control that sets a native setting is the native one, every
pass read from a film pass has its channels, every film pass has a Blender pass, every
preset is a setting the renderer accepts; and without the native module the add-on still
registers and a render says what to do."""

import json
import os
import subprocess
import sys
from dataclasses import asdict, fields

import bpy
import pytest
from whitted import result
from whitted.properties.presets import NEW_SCENE, PRESETS, Quality, preset

# scene.whitted's controls that are native Settings fields: control -> field.
SCENE_SETTINGS = {
    "max_depth": "max_depth",
    "aa_mode": "aa_mode",
    "aa_samples": "aa_samples",
    "aa_threshold": "aa_threshold",
    "aa_depth": "aa_depth",
    "glossy_samples": "glossy_samples",
    "emitter_samples": "emitter_samples",
    "fresnel": "fresnel",
    "glass_shadows": "glass_shadows",
    "cutoff": "cutoff",
    "tile_size": "tile_size",
    "use_waves": "waves",
    "adaptive_sampling": "adaptive_sampling",
    "noise_threshold": "noise_threshold",
    "adaptive_min_samples": "adaptive_min_samples",
}
# A new scene's quality controls start at the NEW_SCENE preset's values, on purpose; the
# others at the native defaults.
SCENE_OWN_DEFAULTS = {
    name: value for name, value in asdict(preset(NEW_SCENE)).items() if name in SCENE_SETTINGS
}


def _native_default(native, field):
    value = getattr(native.Settings(), field)
    return getattr(value, "name", value)


def _check_control(rna, native, field, default):
    if isinstance(default, float):
        assert rna.default == pytest.approx(default, rel=1e-7), rna.identifier
    else:
        assert rna.default == default, rna.identifier
    if field in native.LIMITS:
        assert (rna.hard_min, rna.hard_max) == pytest.approx(native.LIMITS[field]), field


def test_scene_controls_take_the_native_defaults_and_ranges(empty_scene, native):
    properties = empty_scene.whitted.bl_rna.properties
    for control, field in SCENE_SETTINGS.items():
        default = SCENE_OWN_DEFAULTS.get(control, _native_default(native, field))
        _check_control(properties[control], native, field, default)
    assert properties["aa_samples"].default != native.Settings().aa_samples  # still a choice
    low, high = native.LIMITS["light_samples"]
    assert (properties["light_samples"].hard_min, properties["light_samples"].hard_max) == (
        low,
        high,
    )


def test_view_layer_and_light_controls_take_the_native_ranges(empty_scene, native):
    depth = bpy.context.view_layer.whitted.bl_rna.properties["contribution_depth"]
    _check_control(depth, native, "contribution_depth", native.Settings().contribution_depth)
    assert native.LIMITS["contribution_depth"][1] == result.MAX_CONTRIBUTION_DEPTH
    samples = bpy.types.Light.bl_rna.properties["whitted"].fixed_type.properties["samples"]
    assert samples.hard_max == native.LIMITS["light_samples"][1]
    assert samples.hard_min == 0  # the scene's Shadow Samples


def test_each_pass_has_the_channels_of_its_film_pass(native):
    film = native.FILM_PASSES
    from_film = [spec for spec in result.PASSES if spec.source in film]
    for spec in from_film:
        assert spec.first == 0
        assert len(spec.channels) == film[spec.source], spec.name
    others = {spec.source for spec in result.PASSES if spec.source not in film}
    assert others == result.IMAGE_SOURCES
    # The per-depth passes share Contributions, one bin of its channels each.
    bins = result.contribution_passes(result.MAX_CONTRIBUTION_DEPTH)
    for depth, spec in enumerate(bins):
        assert spec.source == "contributions"
        assert (spec.first, len(spec.channels)) == (
            depth * film["contributions"],
            film[spec.source],
        )
    # Every film pass reaches Blender: adding one in C++ without its Blender entry fails.
    assert {spec.source for spec in from_film} | {"contributions"} == set(film)


def test_every_preset_is_a_setting_the_renderer_accepts(native):
    # Every numeric quality control has a native range.
    numeric = {field.name for field in fields(Quality) if field.type in (int, float)}
    assert numeric <= set(native.LIMITS)
    for key, _, _, quality in PRESETS:
        values = asdict(quality)
        for name in numeric:
            low, high = native.LIMITS[name]
            assert low <= values[name] <= high, (key, name)
        settings = native.Settings(
            aa_mode=getattr(native.AntiAliasing, quality.aa_mode),
            fresnel=getattr(native.Fresnel, quality.fresnel),
        )
        for name in numeric - {"light_samples"}:
            setattr(settings, name, values[name])
        settings.validate()
        assert native.Light(samples=quality.light_samples).samples == quality.light_samples


# Run in a new Blender: the add-on enabled where whitted_native cannot be imported.
_WITHOUT_NATIVE = """
import json, sys
sys.modules["whitted.whitted_native"] = None  # as if no module were built for this Python
import bpy
from whitted_tools.blender import addon_problem
out = {"problem": addon_problem()}
import whitted.native_tables
out["native"] = whitted.native_tables.NATIVE is not None
scene = bpy.context.scene
scene.render.engine = "WHITTED"
out["engine"] = scene.render.engine
out["max_depth"] = scene.whitted.max_depth
camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
scene.collection.objects.link(camera)
scene.camera = camera
scene.render.resolution_x = scene.render.resolution_y = 8
try:
    bpy.ops.render.render()
except RuntimeError as error:
    out["report"] = str(error)
print("RESULT " + json.dumps(out))
"""


def test_without_the_native_module_the_addon_registers_and_a_render_says_why(tmp_path):
    binary = bpy.app.binary_path
    if binary and os.path.basename(binary).startswith("blender"):
        command = [binary, "-b", "--factory-startup", "--python-expr", _WITHOUT_NATIVE]
    else:  # Blender as a Python module
        command = [sys.executable, "-c", _WITHOUT_NATIVE]
    # (Its exit code is the failed render's.)
    run = subprocess.run(command, capture_output=True, text=True, timeout=120)
    lines = [line for line in run.stdout.splitlines() if line.startswith("RESULT ")]
    assert lines, run.stdout + run.stderr
    line = lines[0]
    out = json.loads(line[len("RESULT ") :])
    assert out["problem"] is None
    assert out["native"] is False
    assert out["engine"] == "WHITTED"
    assert out["max_depth"] == 0  # no native default to take
    assert "Build it from the repository root" in out["report"]
