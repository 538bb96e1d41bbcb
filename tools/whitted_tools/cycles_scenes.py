"""Diffuse-only scenes lit by one light, rendered by Whitted and by Cycles at
direct-light settings, and the measures that compare the two renders.

Shared by tests/blender/test_cycles_lights.py and whitted_tools gallery-lights.

The floor and the blocker use a Diffuse BSDF (roughness 0): Lambertian in
Cycles 3.x and 4.x+ alike. A Principled BSDF is not: in 3.x its diffuse lobe is
Disney's (retro-reflection and grazing darkening at every roughness); in 4.x+
it is Lambertian only with the specular layer off. The viewport display values
of the material say the same (same colour, specular 0), so the comparison does
not depend on how the Diffuse BSDF node is mapped.

Cycles renders direct light only (no bounces), without denoising or adaptive
sampling, with a fixed seed (CPU renders are then the same every run) and a
0.01-pixel filter, so each pixel is sampled at its centre as Whitted does with
one AA sample. Both write 32-bit float OpenEXR, which holds linear radiance.
"""

import math
import os
from dataclasses import dataclass, field

import bpy
import numpy as np
from bpy_extras.object_utils import world_to_camera_view
from mathutils import Vector

from whitted_tools.material_scenes import lambert_material, plain_film
from whitted_tools.metrics import subject_figures

WIDTH, HEIGHT = 64, 48
ALBEDO = 0.8
# Cycles samples per pixel: enough that its noise stays well under the bounds.
CYCLES_SAMPLES = 512
# Whitted's shadow feelers per axis for sized lights in these scenes.
WHITTED_LIGHT_SAMPLES = 8
# Pixels darker than this in Cycles are left out of the ratio (shadow cores).
DARK = 1e-3


@dataclass(frozen=True)
class Case:
    """One light in the standard scene. `settings` are set on the light data,
    `rotation` (Euler XYZ, degrees) on its object."""

    name: str
    type: str
    location: tuple[float, float, float]
    settings: dict = field(default_factory=dict)
    rotation: tuple[float, float, float] = (0.0, 0.0, 0.0)
    # Bounds from measurements (docs/GALLERY.md) with about 3x margin: hard
    # shadows agree to a few 1e-4; soft ones differ by Cycles' noise and by
    # Whitted's 8 x 8 stratified feelers (bands in the penumbra).
    max_relative_rmse: float = 0.01  # RMSE / mean(Cycles)
    max_profile_error: float = 0.02  # along the shadow row, / its brightest pixel
    # The Light properties the case needs (for Blender 4.x+-only cases).
    requires: tuple[str, ...] = ()


# Bounds for a light with a size (soft shadows).
SOFT = {"max_relative_rmse": 0.03, "max_profile_error": 0.1}

# A spot above the scene, aimed at the origin from (1.5, -1, 3).
_SPOT_ROTATION = (26.6, 0.0, 56.3)

CASES = (
    Case("point", "POINT", (1.0, -1.0, 3.0), {"energy": 500.0, "shadow_soft_size": 0.0}),
    Case(
        "point_radius",
        "POINT",
        (1.0, -1.0, 3.0),
        {"energy": 500.0, "shadow_soft_size": 0.5},
        **SOFT,
    ),
    Case(
        "spot",
        "SPOT",
        (1.5, -1.0, 3.0),
        {
            "energy": 800.0,
            "shadow_soft_size": 0.0,
            "spot_size": math.radians(50.0),
            "spot_blend": 0.3,
        },
        rotation=_SPOT_ROTATION,
    ),
    Case(
        "sun",
        "SUN",
        (0.0, 0.0, 5.0),
        {"energy": 3.0, "angle": 0.0},
        rotation=(30.0, 0.0, 30.0),
    ),
    Case(
        "sun_angle",
        "SUN",
        (0.0, 0.0, 5.0),
        {"energy": 3.0, "angle": math.radians(10.0)},
        rotation=(30.0, 0.0, 30.0),
        **SOFT,
    ),
    Case(
        "area_square",
        "AREA",
        (0.5, -0.5, 2.5),
        {"energy": 300.0, "shape": "SQUARE", "size": 1.0},
        **SOFT,
    ),
    Case(
        "area_rectangle",
        "AREA",
        (0.5, -0.5, 2.5),
        {"energy": 300.0, "shape": "RECTANGLE", "size": 1.5, "size_y": 0.5},
        rotation=(0.0, 0.0, 30.0),
        **SOFT,
    ),
    Case(
        "area_disk",
        "AREA",
        (0.5, -0.5, 2.5),
        {"energy": 300.0, "shape": "DISK", "size": 1.0},
        **SOFT,
    ),
    Case(
        "area_ellipse",
        "AREA",
        (0.5, -0.5, 2.5),
        {"energy": 300.0, "shape": "ELLIPSE", "size": 1.5, "size_y": 0.6},
        rotation=(0.0, 0.0, -20.0),
        **SOFT,
    ),
    # Blender 4.x+: `normalize` off. A point's intensity is then P / pi (radius 0)
    # or P r^2, a sun's irradiance S pi sin^2(angle / 2), an area's radiance P / pi.
    Case(
        "point_unnormalized",
        "POINT",
        (1.0, -1.0, 3.0),
        {"energy": 125.0, "shadow_soft_size": 0.0, "normalize": False},
        requires=("normalize",),
    ),
    Case(
        "point_radius_unnormalized",
        "POINT",
        (1.0, -1.0, 3.0),
        {"energy": 640.0, "shadow_soft_size": 0.25, "normalize": False},
        **SOFT,
        requires=("normalize",),
    ),
    Case(
        "sun_angle_unnormalized",
        "SUN",
        (0.0, 0.0, 5.0),
        {"energy": 125.0, "angle": math.radians(10.0), "normalize": False},
        rotation=(30.0, 0.0, 30.0),
        **SOFT,
        requires=("normalize",),
    ),
    Case(
        "area_unnormalized",
        "AREA",
        (0.5, -0.5, 2.5),
        {"energy": 225.0, "shape": "RECTANGLE", "size": 1.5, "size_y": 0.5, "normalize": False},
        **SOFT,
        requires=("normalize",),
    ),
)


def supported(case):
    """Whether this Blender's lights have every property the case sets."""
    probe = bpy.data.lights.new("probe", case.type)
    try:
        return all(hasattr(probe, name) for name in case.requires)
    finally:
        bpy.data.lights.remove(probe)


def _mesh_object(scene, name, vertices, faces, location, material):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(vertices, [], faces)
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    obj.location = location
    scene.collection.objects.link(obj)
    return obj


def _box(half):
    vertices = [(x, y, z) for x in (-half, half) for y in (-half, half) for z in (-half, half)]
    # Corner index = 4x + 2y + z with each of x, y, z 0 (low) or 1 (high); faces outward.
    faces = [
        (0, 1, 3, 2),
        (4, 6, 7, 5),
        (0, 4, 5, 1),
        (2, 3, 7, 6),
        (0, 2, 6, 4),
        (1, 5, 7, 3),
    ]
    return vertices, faces


def build_scene(scene, case):
    """Fill the (empty) `scene` with the floor, the blocker, the camera and the
    case's light; returns the light object."""
    material = lambert_material(albedo=ALBEDO)
    floor = 3.0
    _mesh_object(
        scene,
        "Floor",
        [(-floor, -floor, 0.0), (floor, -floor, 0.0), (floor, floor, 0.0), (-floor, floor, 0.0)],
        [(0, 1, 2, 3)],
        (0.0, 0.0, 0.0),
        material,
    )
    # A floating box: its shadow on the floor is whole, with an edge all round.
    _mesh_object(scene, "Blocker", *_box(0.35), (-0.2, 0.33, 0.9), material)

    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.location = (0.0, -5.0, 4.5)
    camera.rotation_euler = (
        (Vector((0.0, 0.3, 0.0)) - camera.location).to_track_quat("-Z", "Y").to_euler()
    )
    camera.data.lens = 40.0
    scene.collection.objects.link(camera)
    scene.camera = camera

    light = bpy.data.lights.new(case.name, case.type)
    for key, value in case.settings.items():
        setattr(light, key, value)
    light.whitted.samples = WHITTED_LIGHT_SAMPLES
    light_object = bpy.data.objects.new("Light", light)
    light_object.location = case.location
    light_object.rotation_euler = tuple(math.radians(a) for a in case.rotation)
    scene.collection.objects.link(light_object)

    # No world: black background and no ambient term in either engine.
    plain_film(scene, WIDTH, HEIGHT)
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    return light_object


def set_cycles_reference(scene, samples, specular_bounces=0, max_bounces=None):
    """Cycles as the reference Whitted is compared with: on the CPU, `samples` per pixel
    at a fixed seed, no adaptive sampling, no denoising, no clamping; no diffuse or
    volume bounce (what a Whitted ray tree leaves out), glossy, transmission and
    transparent bounces up to `specular_bounces` (the mirror and glass rays it traces),
    without caustics; `max_bounces` the total, by default `specular_bounces`."""
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.samples = samples
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.seed = 0
    cycles.use_animated_seed = False
    cycles.max_bounces = specular_bounces if max_bounces is None else max_bounces
    cycles.diffuse_bounces = 0
    cycles.volume_bounces = 0
    cycles.glossy_bounces = cycles.transmission_bounces = specular_bounces
    cycles.transparent_max_bounces = specular_bounces
    cycles.caustics_reflective = cycles.caustics_refractive = False
    cycles.sample_clamp_direct = cycles.sample_clamp_indirect = 0.0


def set_cycles_direct_light(scene, samples=CYCLES_SAMPLES):
    """Cycles: direct light only, deterministic, no denoising, a centre-point filter."""
    set_cycles_reference(scene, samples)
    scene.cycles.filter_width = 0.01


def box_filtered(scene, cycles_samples, whitted_samples):
    """Both engines averaging over the pixel alike, for effects that spread samples over
    it (the lens, the shutter, thin strands): Cycles at direct-light settings with
    `cycles_samples` and a box filter one pixel wide, Whitted on a jittered grid of
    `whitted_samples` per axis."""
    set_cycles_direct_light(scene, samples=cycles_samples)
    scene.cycles.pixel_filter_type = "BOX"
    scene.cycles.filter_width = 1.0
    scene.whitted.pixel_filter_type = "BOX"
    scene.whitted.aa_mode = "JITTERED"
    scene.whitted.aa_samples = whitted_samples


def set_whitted_direct_light(scene):
    """Whitted: one sample at each pixel centre, no reflection or refraction rays."""
    scene.whitted.aa_samples = 1
    scene.whitted.max_depth = 0


def render_exr(scene, engine, path):
    """Render `scene` with `engine` to a 32-bit float OpenEXR at `path`; returns its
    linear RGB pixels, float32[height, width, 3], rows bottom to top."""
    return render_rgba(scene, engine, path)[..., :3]


def render_rgba(scene, engine, path):
    """As render_exr, with alpha: float32[height, width, 4]."""
    scene.render.engine = engine
    settings = scene.render.image_settings
    settings.file_format = "OPEN_EXR"
    settings.color_depth = "32"
    settings.color_mode = "RGBA"
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    return read_rgba(path)


def read_rgba(path):
    """The pixels of the image file at `path` as Blender reads them: float32[height,
    width, 4], bottom row first."""
    image = bpy.data.images.load(str(path))
    try:
        width, height = image.size
        pixels = np.empty(width * height * 4, dtype=np.float32)
        image.pixels.foreach_get(pixels)
    finally:
        bpy.data.images.remove(image)
    return pixels.reshape(height, width, 4)


def effect_figures(label, image, sharp, cycles):
    """An effect's render `image` and the same scene's with it off (`sharp`) against
    Cycles' `cycles` (linear RGBA): (SSIM, luminance ratio) of `image`, the SSIM of
    `sharp`, and each one's mean absolute difference from Cycles (linear RGB); printed
    under `label`."""
    value, ratio = subject_figures(image, cycles)
    sharp_value, _ = subject_figures(sharp, cycles)
    error = float(np.abs(image[..., :3] - cycles[..., :3]).mean())
    sharp_error = float(np.abs(sharp[..., :3] - cycles[..., :3]).mean())
    print(
        f"\n{label}: SSIM {value:.4f} (sharp {sharp_value:.4f}), ratio {ratio:.4f}, "
        f"mean difference {error:.5f} (sharp {sharp_error:.5f})"
    )
    return (value, ratio), sharp_value, error, sharp_error


def render_both(scene, case, directory):
    """Build `case` in `scene` and render it with Whitted and Cycles into
    `directory`; returns (whitted, cycles) linear RGB pixels."""
    build_scene(scene, case)
    set_whitted_direct_light(scene)
    set_cycles_direct_light(scene)
    whitted = render_exr(scene, "WHITTED", os.path.join(directory, f"{case.name}_whitted.exr"))
    cycles = render_exr(scene, "CYCLES", os.path.join(directory, f"{case.name}_cycles.exr"))
    return whitted, cycles


@dataclass(frozen=True)
class Comparison:
    mean_ratio: float  # mean(Whitted) / mean(Cycles) over pixels Cycles shows lit
    relative_rmse: float  # RMSE(Whitted - Cycles) / mean(Cycles), all pixels
    profile_error: float  # largest difference along the shadow row / its brightest pixel
    row: int  # the shadow row, from the bottom


def compare(scene, whitted, cycles):
    """Measures on the RGB channels of two linear renders of `scene`."""
    lit = cycles.mean(axis=-1) > DARK
    row = shadow_row(scene)
    return Comparison(
        mean_ratio=float(whitted[lit].mean() / cycles[lit].mean()),
        relative_rmse=float(np.sqrt(np.mean((whitted - cycles) ** 2)) / cycles.mean()),
        profile_error=_profile_error(whitted, cycles, row),
        row=row,
    )


def shadow_row(scene):
    """Image row (from the bottom) through the middle of the blocker's shadow: where
    the line from the light through the blocker's centre meets the floor."""
    light = scene.objects["Light"]
    centre = scene.objects["Blocker"].location
    if light.data.type == "SUN":
        direction = light.matrix_world.to_3x3() @ Vector((0.0, 0.0, -1.0))
    else:
        direction = centre - light.matrix_world.translation
    floor_point = centre - direction * (centre.z / direction.z)
    view = world_to_camera_view(scene, scene.camera, floor_point)
    return int(view.y * scene.render.resolution_y)


def _profile_error(whitted, cycles, row):
    """Largest difference along image `row`, as a share of that row's brightest
    Cycles pixel: a penumbra of the wrong width or place shows here."""
    w = whitted[row].mean(axis=-1)
    c = cycles[row].mean(axis=-1)
    return float(np.abs(w - c).max() / c.max())
