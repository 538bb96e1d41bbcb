"""POV-Ray 3.7 through Blender's own render_povray add-on, set up to render what Whitted renders.

Issue 7 compares Whitted with POV-Ray on the same .blend file. POV-Ray is driven the way an
artist would drive it: Blender 3.4's bundled add-on `render_povray` (engine 'POVRAY_RENDER')
exports the scene, runs `povray` and reads the image back. Nothing here writes .pov text: the
add-on's own properties (`scene.pov`, `material.pov*`, `world.pov`, `light.pov`) are set from
the Whitted settings and from the same material mapping Whitted uses.

whitted_tools perf-povray renders a saved scene this way; whitted_tools perf-render uses it for the
performance suite. Inside Blender:

    configure(scene)            -> dict: enable the add-on, choose its engine, set its properties
    render(scene, image_path)   -> dict: render one frame through the add-on and time it

`configure` changes only POV-only properties and `scene.render.engine`. The add-on also reads
Blender properties that Whitted reads too (a material's `use_nodes`, viewport colour and
metallic; a light's colour). `render` sets those for the duration of the render call only and
restores them afterwards, so the scene renders the same in Whitted before and after.

Timing (`render` returns):
    render_seconds        wall time of `bpy.ops.render.render()` (export, POV-Ray, reading the
                          image back); writing the PNG afterwards is not included. The add-on
                          sleeps 0.5 s before each poll of POV-Ray and 0.5 s more before
                          reading the image, so this includes 1-1.5 s of the add-on's waiting.
    povray_seconds        POV-Ray's own "Trace Time" wall seconds: the figure in parentheses on
                          the "Trace Time:" line of the "Render Time:" block POV-Ray writes at
                          the end of a render (photon and radiosity passes are off here).
    povray_parse_seconds  the "Parse Time:" wall seconds of the "Parser Time" block.
    threads               the "using N thread(s)" of the Trace Time line.
Both blocks are read from the text stream file (All_File) POV-Ray writes for the same run.

Mapping of Whitted's settings (`scene.whitted`) to the add-on's (`scene.pov`):
    max_depth     max_trace_level = max_depth + 1: POV-Ray counts the camera ray as level 1
                  (at most 256, the add-on's limit).
    cutoff        adc_bailout (the add-on writes it only with "Advanced" global settings on and
                  radiosity off, so both are set; the other advanced values get POV defaults).
    aa_mode, aa_samples, aa_threshold, aa_depth:
        REGULAR n x n, n >= 2: Sampling_Method 1 with threshold 0 and depth n. Method 1 traces
            the pixel centre, then supersamples every pixel whose colour differs from its left
            or top neighbour by >= the threshold with an n x n grid at the cell centres (the
            same positions as Whitted's grid); threshold 0 supersamples every pixel. POV-Ray
            averages the centre sample in too (n*n + 1 samples per pixel) and traces one extra
            row and column per block. Measured on an 80 x 60 image: depth 2 -> 19200 = 4 x
            4800 supersamples, depth 3 -> 43200 = 9 x 4800. n is limited to 9 (POV's maximum).
        REGULAR 1 x 1: anti-aliasing off (one camera ray through the pixel centre).
        JITTERED: as REGULAR with Jitter on, amount 1 (each sample moves within its cell);
            1 x 1 jittered is off (centre sample).
        ADAPTIVE: Sampling_Method 2 (Whitted's corner subdivision) with the same threshold
            and depth aa_depth + 1: POV-Ray's depth d splits a pixel at most d - 1 times
            (measured: depth 1 -> corners only, depth 2 -> 5 extra samples per pixel = one
            split, depth 3 -> 21 = two splits), Whitted's aa_depth d splits d times. The
            add-on limits the threshold to 1.0 (Whitted allows 3). Antialias_Gamma is 1, so
            POV compares linear colours as Whitted does; POV splits when any two corners
            differ by >= the threshold (sum of |dR|+|dG|+|dB|+|dAlpha|), Whitted when the sum
            over R, G, B of the corners' spread exceeds it.
    fresnel       EXACT: `reflection { T fresnel on }` with `conserve_energy`: POV-Ray's
                  Fresnel term is the exact unpolarised dielectric formula with the interior's
                  IOR, and conserve_energy scales the refracted light by 1 - F * T.
                  SCHLICK: the same exact formula (POV-Ray has no Schlick option).
                  OFF: fixed weights, no conserve_energy.
    threads       scene.render.threads (what Whitted uses) is passed as +WT<n>.

Materials: each material in use goes through Whitted's own exporter (`whitted.export.material.
convert_material`: Principled, Glossy, Glass, ... nodes, the viewport values of a material
without nodes, and the Whitted material override), and the resulting Whitted parameters are
set on the add-on's material properties. With lights of POV colour E/pi (see Lights), POV's
`diffuse 1` on a pigment kd equals Whitted's kd/pi * E. The add-on reads the pigment from the
material's viewport colour and ignores a Blender node tree, so during the render each
material's `use_nodes` is off, its viewport colour is the pigment and its viewport metallic
is 0 (the add-on turns it into a `metallic` reflection tint).
    diffuse kd            pigment rgb = kd (divided by the opacity below), diffuse 1, brilliance 1
                          (Lambert), ambient = Whitted's ka.
    specular ks, exponent f   phong = max(ks) * (f + 2) / 2 (Whitted's normalised Phong lobe;
                          POV's phong has no (f + 2) / 2pi factor and no cosine to the light),
                          phong_size = f. The add-on limits phong to 1 and phong_size to
                          511 / 3.14 = 163: a sharp glass highlight comes out wider and dimmer.
    reflectivity R        reflection rgb R (raytrace mirror on, exponent 1, no metallic tint).
    transmissivity T      pigment rgb T with filter 1 (raytrace transparency, alpha 0): the
                          refracted ray is weighted by T, and so are shadow rays through it, as
                          in Whitted. interior ior = Whitted's IOR. Fake caustics, photons and
                          distance fading (fade colour white) are off.
    alpha a < 1           transmit 1 - a with IOR 1 (light passes straight through).
    emission              finish emission = max(emission) / max(pigment) (POV scales emission
                          by the pigment; black pigment cannot emit).
The add-on writes three texture indices per mesh triangle (meant for vertex colours), even
when all three are the same material. POV-Ray then shades each hit three times, each with its
own reflected and refracted rays, so the ray tree of glass and mirrors grows as 3^depth: on
the demo scene the same .pov with one index per triangle traces 3-4x faster. This is the
add-on's path and is timed as is.
Not expressible through the add-on (approximated, listed in the result's "unmatched"):
textures (a textured diffuse colour uses the material's viewport colour times the diffuse
weight), a mirror part R together with Fresnel glass (the add-on writes one reflection colour:
T with Fresnel, R is dropped), coloured transmission combined with a diffuse part (grey
transmit of max(T)), a coloured highlight (phong is grey), alpha textures.

World: background (`world.pov.horizon_color`) = Whitted's background radiance; ambient light
(`world.pov.ambient_color` and the advanced global `ambient_light`) = Whitted's Ia.

Lights: the add-on writes each light's colour (as sRGB) and ignores its power, so during the
render each light's colour is set to the POV intensity that makes POV's diffuse term equal to
Whitted's (Blender 3.x units, as addon/export/light.py):
    sun      parallel light of colour c * S / pi (S: strength in W/m^2).
    point    colour c * P / (4 pi^2 D) with fade_power 2 and the add-on's fade_distance
    spot     sqrt(D / 2) from the light's (legacy) distance D = 0.01: POV's attenuation
             2 / (1 + (d / fd)^2) = D / (D / 2 + d^2) is D / d^2 to within 1% beyond 0.71 m,
             so the light gives c * P / (4 pi^2 d^2) = (c * P / (4 pi d^2)) / pi = E / pi.
    area     colour c * P / (2 pi D^2) with the add-on's fade_distance D / 2, D = 0.1, and
             area_light n x n (Whitted's shadow samples, regular, no jitter): on axis
             Whitted's E / pi = P / (4 pi d^2); POV's D^2 / (2 d^2) is within 1% beyond 0.5 m.
             POV's area light is a grid of point lights: it shines both ways and without
             the emitter's cosine (off axis it is brighter by 1 / cos), and a disk or
             ellipse becomes a rectangle.
    shadows  a light whose shadow switch is off is `shadowless`.
Point and spot radius and the sun's angle (soft shadows) have no counterpart in the add-on:
their shadows are hard. The add-on exports every light object in the file that is not hidden
for rendering, also those of other scenes.

POV-Ray reads a user configuration (~/.povray/3.7/povray.conf) and warns when there is none.
`render` writes one into its temporary directory, allowing POV-Ray to read its include files
and read and write in that directory only, and points HOME there for the render call; the
add-on writes the .pov, .ini, image and text stream into the same directory
(`scene.pov.scene_path`, temporary files off), which is removed afterwards unless `work_dir`
is given.
"""

import contextlib
import functools
import importlib
import math
import os
import re
import tempfile
import time
import types

import bpy

from whitted_tools.blender import addon_problem

POV_ADDON = "render_povray"
POV_ENGINE = "POVRAY_RENDER"
WHITTED_ADDON = "whitted"

# The add-on's limits (render_properties.py, shading_properties.py).
POV_MAX_TRACE_LEVEL = 256
POV_MAX_AA_DEPTH = 9
POV_MAX_AA_THRESHOLD = 1.0
POV_MAX_PHONG = 1.0
POV_HARDNESS_PER_PHONG_SIZE = 3.14  # the add-on writes phong_size = specular_hardness / 3.14
POV_MAX_HARDNESS = 511

# Legacy light distances that make POV's fade a plain inverse square law (see the docstring).
POINT_FADE_DISTANCE = 0.01
AREA_FADE_DISTANCE = 0.1

# The stream file POV-Ray writes beside its image when the .ini says All_File=1.
POV_LOG_NAME = "alltext.out"
POV_SCENE_NAME = "scene"
POV_INCLUDE_DIR = "/usr/share/povray-3.7"

# "  Trace Time:       0 hours  0 minutes  0 seconds (0.176 seconds)
#                using 2 thread(s) with 0.232 CPU-seconds total"
_TIME_RE = re.compile(
    r"^\s*(?P<name>Parse|Bounding|Photon|Radiosity|Trace) Time:\s+"
    r"\d+ hours\s+\d+ minutes\s+\d+ seconds \((?P<wall>[\d.]+) seconds\)\s*\n"
    r"\s*using (?P<threads>\d+) thread\(s\) with (?P<cpu>[\d.]+) CPU-seconds total",
    re.MULTILINE,
)


def configure(scene):
    """Enable render_povray, make it the scene's engine and set its properties so that
    POV-Ray renders what Whitted renders. Returns the mapped settings (JSON-ready)."""
    _enable_addon(POV_ADDON)
    plan = _plan(scene)
    scene.render.engine = POV_ENGINE
    for owner, values in plan["pov"]:
        _assign(owner, values)
    return plan["settings"]


def render(scene, image_path, work_dir=None):
    """Render one frame through the add-on into `image_path` (PNG when it ends in .png)
    and return the times (see the module docstring) and the mapped settings.

    `work_dir` keeps the add-on's files (.pov, .ini, POV-Ray's image and text stream) there;
    by default they go to a temporary directory that is removed afterwards.
    """
    if scene.render.engine != POV_ENGINE:
        raise RuntimeError(f"povray: the engine is {scene.render.engine!r}; call configure()")
    plan = _plan(scene)
    threads = scene.render.threads
    if work_dir is None:
        with tempfile.TemporaryDirectory(prefix="whitted_povray_") as temp_dir:
            return _render_in(scene, image_path, temp_dir, threads, plan)
    os.makedirs(work_dir, exist_ok=True)
    return _render_in(scene, image_path, os.path.abspath(work_dir), threads, plan)


def _render_in(scene, image_path, work_dir, threads, plan):
    run = [
        (
            scene.pov,
            {
                # Files in work_dir, kept until we have read POV-Ray's text stream.
                "tempfiles_enable": False,
                "deletefiles_enable": False,
                "scene_path": work_dir,
                "scene_name": POV_SCENE_NAME,
                # As many render threads as Whitted uses (scene.render.threads).
                "command_line_switches": f"+WT{threads}",
            },
        ),
    ]
    if image_path.lower().endswith(".png"):
        # For save_render below.
        run.append((scene.render.image_settings, {"file_format": "PNG"}))
    overrides = [(o, k, v) for o, values in run for k, v in values.items()] + plan["native"]
    with _povray_user_config(work_dir), _overridden(overrides):
        start = time.perf_counter()
        outcome = bpy.ops.render.render()
        render_seconds = time.perf_counter() - start
        if "FINISHED" not in outcome:
            raise RuntimeError(f"povray: the render returned {outcome}")
        log = _read_log(os.path.join(work_dir, POV_LOG_NAME))
        times = _parse_times(log)
        if "Trace" not in times:
            raise RuntimeError(f"povray: no Trace Time in POV-Ray's output:\n{log[-2000:]}")
        bpy.data.images["Render Result"].save_render(os.path.abspath(image_path), scene=scene)
    return {
        "render_seconds": render_seconds,
        "povray_seconds": times["Trace"]["wall"],
        "povray_parse_seconds": times.get("Parse", {}).get("wall", 0.0),
        "threads": times["Trace"]["threads"],
        "povray_times": times,
        "resolution": _resolution(scene),
        "image": os.path.abspath(image_path),
        "settings": plan["settings"] | {"threads_requested": threads},
    }


# ----------------------------------------------------------------------------- planning


def _plan(scene):
    """The whole mapping as data, reading the scene only.

    Returns {"pov": [(owner, {property path: value})] for configure(), "native": [(owner,
    attribute, value)] for the render call, "settings": a JSON-ready summary}.
    """
    whitted_export = _whitted_export()
    w = scene.whitted
    warnings = []
    unmatched = []
    aa, aa_notes = _antialias(w)
    unmatched += aa_notes
    max_trace_level = min(w.max_depth + 1, POV_MAX_TRACE_LEVEL)
    if w.max_depth + 1 > POV_MAX_TRACE_LEVEL:
        unmatched.append(f"max_depth {w.max_depth} is beyond POV's max_trace_level 256")
    world = whitted_export.world.convert_world(scene.world, w.ambient_strength, warnings)
    scene_pov = {
        # Ray depth: POV-Ray counts the camera ray as level 1.
        "max_trace_level": max_trace_level,
        # Adaptive depth control; written only with advanced settings on and radiosity off.
        "global_settings_advanced": True,
        "radio_enable": False,
        "adc_bailout": w.cutoff,
        # The other advanced global settings, at POV-Ray's defaults.
        "irid_wavelength": (0.25, 0.18, 0.14),
        "number_of_waves": 10,
        "noise_generator": 2,
        # Whitted's ambient light Ia (the world also writes it; both the same).
        "ambient_light": world.ambient,
        # A Whitted tracer: no photons, media, baking; shadows on (per light below).
        "photon_enable": False,
        "media_enable": False,
        "baking_enable": False,
        "use_shadows": True,
        # Export without comments or indentation: less text to write and parse.
        "comments_enable": False,
        "indentation_character": "NONE",
        # Render the scene, not a text block.
        "text_block": "",
        **aa,
    }
    pov = [(scene.pov, scene_pov)]
    native = []
    world_settings = {"background": world.background, "ambient": world.ambient}
    if scene.world is not None:
        pov.append(
            (
                scene.world.pov,
                {
                    # A flat background of Whitted's background radiance.
                    "use_sky_blend": False,
                    "horizon_color": world.background,
                    # Ia of the ambient term.
                    "ambient_color": world.ambient,
                },
            )
        )
    materials = {}
    for material in bpy.data.materials:
        if material.users == 0:
            continue  # the add-on exports only materials in use
        exported = whitted_export.material.convert_material(material, warnings)
        values, overrides, notes = _material(material, exported.data, w.fresnel)
        pov.append((material, values))
        native += overrides
        materials[material.name] = _summary(values) | _overrides_summary(overrides)
        unmatched += [f"material '{material.name}': {note}" for note in notes]
    lights = {}
    for light, name in _scene_lights(scene):
        values, overrides, notes = _light(light, w.light_samples, whitted_export.light)
        pov.append((light, values))
        native += overrides
        lights[name] = _summary(values) | _overrides_summary(overrides)
        unmatched += [f"light '{name}': {note}" for note in notes]
    settings = {
        "engine": POV_ENGINE,
        "whitted": {
            "max_depth": w.max_depth,
            "cutoff": w.cutoff,
            "aa_mode": w.aa_mode,
            "aa_samples": w.aa_samples,
            "aa_threshold": w.aa_threshold,
            "aa_depth": w.aa_depth,
            "fresnel": w.fresnel,
            "light_samples": w.light_samples,
            "ambient_strength": w.ambient_strength,
        },
        "pov": _summary(scene_pov),
        "world": world_settings,
        "materials": materials,
        "lights": lights,
        "unmatched": unmatched,
        "warnings": warnings,
    }
    return {"pov": pov, "native": native, "settings": settings}


def _antialias(w):
    """Whitted's anti-aliasing -> the add-on's (scene.pov), and what does not match."""
    notes = []
    n = w.aa_samples
    if w.aa_mode in {"REGULAR", "JITTERED"}:
        if n == 1:
            # One sample per pixel: POV's centre sample, no supersampling.
            if w.aa_mode == "JITTERED":
                notes.append("a 1 x 1 jittered sample is POV's pixel-centre sample")
            return {"antialias_enable": False}, notes
        if n > POV_MAX_AA_DEPTH:
            notes.append(f"{n} x {n} samples is beyond POV's depth 9; using 9 x 9")
        notes.append("POV's method 1 averages an extra pixel-centre sample (n*n + 1)")
        return {
            "antialias_enable": True,
            "antialias_method": "0",  # the add-on writes Sampling_Method=1
            "antialias_threshold": 0.0,  # supersample every pixel
            "antialias_depth": min(n, POV_MAX_AA_DEPTH),  # an n x n grid
            "antialias_gamma": 1.0,
            "jitter_enable": w.aa_mode == "JITTERED",
            "jitter_amount": 1.0,  # anywhere in its cell
        }, notes
    # ADAPTIVE: Whitted's corner subdivision is POV's method 2.
    if w.aa_threshold > POV_MAX_AA_THRESHOLD:
        notes.append(f"AA threshold {w.aa_threshold} is beyond the add-on's 1.0; using 1.0")
    return {
        "antialias_enable": True,
        "antialias_method": "1",  # the add-on writes Sampling_Method=2
        "antialias_threshold": min(w.aa_threshold, POV_MAX_AA_THRESHOLD),
        # POV's depth d splits d - 1 times, Whitted's aa_depth splits aa_depth times.
        "antialias_depth": min(w.aa_depth + 1, POV_MAX_AA_DEPTH),
        "antialias_gamma": 1.0,  # compare linear colours, as Whitted does
        "jitter_enable": False,
    }, notes


def _material(material, data, fresnel):
    """Whitted's MaterialData -> (POV-only properties, render-time overrides, notes)."""
    notes = []
    kd, ks, r, t = data.diffuse, data.specular, data.reflectivity, data.transmissivity
    if data.diffuse_texture:
        # The add-on cannot take Whitted's textures: the viewport colour stands in for the
        # texture (Whitted's textured diffuse is the diffuse weight times the texture).
        kd = tuple(d * c for d, c in zip(kd, material.diffuse_color[:3], strict=True))
        notes.append("diffuse texture replaced by the viewport colour")
    if data.alpha_texture:
        notes.append("alpha texture ignored")
    transmissive = max(t) > 0.0
    coverage = data.alpha
    if transmissive and max(kd) == 0.0 and coverage == 1.0:
        # Glass: all light that is not reflected is refracted, filtered by T (pigment T,
        # filter 1, opacity 0); shadow rays through it are filtered by T too.
        pigment, pov_alpha, pov_filter, ior = t, 0.0, 1.0, data.ior
    elif transmissive or coverage < 1.0:
        # Partly transparent: grey transmit (1 - a) + a * max(T), unfiltered; what stays
        # opaque carries the diffuse colour.
        transmit = (1.0 - coverage) + coverage * max(t)
        pov_alpha, pov_filter = 1.0 - transmit, 0.0
        pigment = tuple(coverage * c / pov_alpha for c in kd) if pov_alpha > 0.0 else kd
        # A cut-out lets light pass unbent (IOR 1); a refracting part keeps its IOR.
        ior = data.ior if transmissive else 1.0
        if transmissive:
            notes.append("transmission with a diffuse part or alpha: grey transmit max(T)")
    else:
        pigment, pov_alpha, pov_filter, ior = kd, 1.0, 0.0, data.ior
    use_fresnel = transmissive and fresnel != "OFF"
    if transmissive and fresnel == "SCHLICK":
        notes.append("Schlick Fresnel rendered with POV's exact Fresnel")
    if use_fresnel:
        # reflection { T fresnel on }: min 0, max T, so F * T is reflected and
        # conserve_energy leaves (1 - F * T) of the refracted light.
        mirror = t
        if max(r) > 0.0:
            notes.append("mirror part R dropped: one reflection colour, used for Fresnel")
    else:
        mirror = r
    shininess = data.shininess
    phong = max(ks) * (shininess + 2.0) / 2.0
    hardness = round(shininess * POV_HARDNESS_PER_PHONG_SIZE)
    if phong > POV_MAX_PHONG:
        notes.append(f"phong {phong:.3g} limited to the add-on's 1.0")
    if phong > 0.0 and hardness > POV_MAX_HARDNESS:
        notes.append(f"Phong exponent {shininess:.4g} limited to the add-on's 163")
    if max(ks) - min(ks) > 1e-6:
        notes.append("coloured highlight rendered grey")
    emit = 0.0
    if max(data.emission) > 0.0:
        emit = max(data.emission) / max(pigment) if max(pigment) > 0.0 else 0.0
        notes.append("emission approximated as pigment * emission")
    values = {
        # Diffuse: Lambert (brilliance 1) of the pigment, no back lighting.
        "pov.diffuse_shader": "LAMBERT",
        "pov.diffuse_intensity": 1.0,
        "pov.translucency": 0.0,
        # Whitted's ambient weight ka on POV's ambient light (the world's Ia).
        "pov.ambient": min(max(data.ambient, 0.0), 1.0),
        "pov.emit": emit,
        # Highlight: Phong, grey.
        "pov.specular_shader": "PHONG",
        "pov.specular_intensity": min(phong, POV_MAX_PHONG),
        "pov.specular_hardness": min(max(hardness, 1), POV_MAX_HARDNESS),
        "pov.specular_color": (1.0, 1.0, 1.0),
        # Fresnel with energy conservation for transmissive surfaces (Whitted's EXACT).
        "pov.conserve_energy": fresnel != "OFF",
        "pov.mirror_use_IOR": use_fresnel,
        # Mirror ray: weight `mirror`, exponent 1 (POV default), sharp.
        "pov_raytrace_mirror.use": max(mirror) > 0.0,
        "pov_raytrace_mirror.reflect_factor": 1.0,
        "pov.mirror_color": tuple(mirror),
        "pov_raytrace_mirror.fresnel": 1.0,  # written as falloff (unused with fresnel on)
        "pov_raytrace_mirror.fresnel_factor": 1.0,  # written as exponent
        "pov_raytrace_mirror.gloss_factor": 1.0,
        # Refraction: raytraced, filter/transmit as above, Whitted's IOR, no fading.
        "pov.use_transparency": pov_alpha < 1.0,
        "pov.transparency_method": "RAYTRACE",
        "pov.alpha": pov_alpha,
        "pov_raytrace_transparency.filter": pov_filter,
        "pov_raytrace_transparency.ior": ior,
        "pov_raytrace_transparency.depth_max": 0.0,
        "pov_raytrace_transparency.falloff": 1.0,
        "pov.interior_fade_color": (1.0, 1.0, 1.0),  # fade to white: no attenuation
        # No fake caustics, photons, subsurface or iridescence.
        "pov.caustics_enable": False,
        "pov.refraction_caustics": False,
        "pov.photons_reflection": False,
        "pov.refraction_type": "1",
        "pov_subsurface_scattering.use": False,
        "pov.irid_enable": False,
        # The add-on's own node system and replacement code stay off.
        "pov.material_use_nodes": False,
        "pov.replacement_text": "",
    }
    overrides = [
        # The add-on writes empty textures for a material shaded by Blender nodes.
        (material, "use_nodes", False),
        # It reads the pigment from the viewport colour...
        (material, "diffuse_color", (*pigment, 1.0)),
        # ... and turns the viewport metallic into a `metallic` reflection tint.
        (material, "metallic", 0.0),
    ]
    return values, overrides, notes


def _light(light, default_samples, light_export):
    """A Blender light -> (POV-only properties, render-time overrides, notes)."""
    notes = []
    owner, switch = light_export.shadow_switch(light)
    values = {
        # Whitted's per-light shadow switch.
        "pov.shadow_method": "RAY_SHADOW" if getattr(owner, switch) else "NOSHADOW",
        "pov.use_halo": False,
    }
    color = tuple(light.color)
    overrides = []
    if light.type in {"POINT", "SPOT"}:
        # I = P / (4 pi) W/sr; POV gives colour * D / d^2 (fade_power 2, fade_distance
        # sqrt(D / 2)), which must be E / pi = I / (pi d^2).
        scale = light.energy / (4.0 * math.pi**2 * POINT_FADE_DISTANCE)
        overrides += [
            (light, "falloff_type", "INVERSE_SQUARE"),
            (light, "distance", POINT_FADE_DISTANCE),
        ]
        if light.shadow_soft_size > 0.0:
            notes.append("radius (soft shadows) not expressible: hard shadows")
    elif light.type == "SUN":
        # A parallel light of colour E / pi, E = strength in W/m^2.
        scale = light.energy / math.pi
        if light.angle > 0.0:
            notes.append("angle (soft shadows) not expressible: hard shadows")
    elif light.type == "AREA":
        # On axis Whitted's E / pi = P / (4 pi d^2) (3.x: L = P / (4 A)); POV's area light
        # gives colour * D^2 / (2 d^2) with fade_distance D / 2 and fade_power 2.
        scale = light.energy / (2.0 * math.pi * AREA_FADE_DISTANCE**2)
        samples = light.whitted.samples or default_samples
        values |= {
            # An n x n regular grid of shadow feelers, as Whitted's.
            "pov.shadow_ray_samples_x": samples,
            "pov.shadow_ray_samples_y": samples,
            "pov.shadow_ray_sample_method": "CONSTANT_JITTERED",
            "pov.use_jitter": False,
        }
        overrides.append((light, "distance", AREA_FADE_DISTANCE))
        notes.append("POV's area light has no emitter cosine and shines both ways")
        if light.shape in {"DISK", "ELLIPSE"}:
            notes.append(f"{light.shape.lower()} area light exported as a rectangle")
    else:
        return values, overrides, [f"light type {light.type} not mapped"]
    # The add-on writes `color srgb <light.color>`: encode, so POV decodes the linear value.
    overrides.append((light, "color", tuple(_srgb_encode(scale * c) for c in color)))
    return values, overrides, notes


def _scene_lights(scene):
    """(light data, object name) of each light object of the scene, each light data once."""
    seen = set()
    for obj in scene.objects:
        if obj.type == "LIGHT" and not obj.hide_render and obj.data.name not in seen:
            seen.add(obj.data.name)
            yield obj.data, obj.name


# ----------------------------------------------------------------------------- helpers


def _enable_addon(name):
    """Enable an add-on for this session (not saved in the preferences)."""
    if name in bpy.context.preferences.addons:
        return
    problem = addon_problem(name)
    if problem:
        raise RuntimeError(f"povray: {problem}")


def _whitted_export():
    """Whitted's exporter modules (the add-on must be installed: scripts/setup.sh)."""
    _enable_addon(WHITTED_ADDON)
    modules = {
        key: importlib.import_module(f"{WHITTED_ADDON}.export.{key}")
        for key in ("material", "world", "light")
    }
    return types.SimpleNamespace(**modules)


def _assign(owner, values):
    """Set each dotted property path of `values` on `owner`."""
    for path, value in values.items():
        *parents, leaf = path.split(".")
        target = functools.reduce(getattr, parents, owner)
        # Only changes: some of the add-on's properties run update callbacks that expect a
        # UI context (material.pov.material_use_nodes raises without an active object).
        if _plain(getattr(target, leaf)) != _plain(value):
            setattr(target, leaf, value)


@contextlib.contextmanager
def _overridden(overrides):
    """Set (owner, attribute, value) for the duration of the block, then restore."""
    saved = []
    try:
        for owner, attribute, value in overrides:
            saved.append((owner, attribute, _plain(getattr(owner, attribute))))
            setattr(owner, attribute, value)
        yield
    finally:
        for owner, attribute, old in reversed(saved):
            setattr(owner, attribute, old)


@contextlib.contextmanager
def _povray_user_config(work_dir):
    """POV-Ray's user configuration in `work_dir/home`, found through HOME: I/O restricted to
    reading its include files and reading and writing `work_dir`."""
    conf_dir = os.path.join(work_dir, "home", ".povray", "3.7")
    os.makedirs(conf_dir, exist_ok=True)
    with open(os.path.join(conf_dir, "povray.conf"), "w", encoding="utf-8") as conf:
        conf.write(
            "[File I/O Security]\nrestricted\n"
            "[Shellout Security]\nforbidden\n"
            f"[Permitted Paths]\nread* = {POV_INCLUDE_DIR}\nread+write* = {work_dir}\n"
        )
    old_home = os.environ.get("HOME")
    os.environ["HOME"] = os.path.join(work_dir, "home")
    try:
        yield
    finally:
        if old_home is None:
            del os.environ["HOME"]
        else:
            os.environ["HOME"] = old_home


def _read_log(path):
    try:
        with open(path, encoding="utf-8", errors="replace") as log:
            return log.read()
    except FileNotFoundError as error:
        raise RuntimeError(f"povray: POV-Ray wrote no text stream {path}") from error


def _parse_times(log):
    """{"Parse"|"Bounding"|"Photon"|"Radiosity"|"Trace": {wall, cpu, threads}}, the last of
    each in POV-Ray's text stream ("Photon Time: No photons" has no entry)."""
    return {
        m["name"]: {"wall": float(m["wall"]), "cpu": float(m["cpu"]), "threads": int(m["threads"])}
        for m in _TIME_RE.finditer(log)
    }


def _plain(value):
    """A property value as a Python scalar or tuple (bpy arrays compare by identity)."""
    return value if isinstance(value, (bool, int, float, str)) else tuple(value)


def _srgb_encode(linear):
    """Linear -> sRGB (extended above 1 by the same curve, as POV-Ray decodes it)."""
    if linear <= 0.0031308:
        return 12.92 * linear
    return 1.055 * linear ** (1.0 / 2.4) - 0.055


def _summary(values):
    """Property values as JSON (colours as tuples)."""
    return {k: _plain(v) for k, v in values.items()}


def _overrides_summary(overrides):
    """Render-time overrides as JSON, named "render.<attribute>"."""
    return {f"render.{attribute}": _plain(value) for _, attribute, value in overrides}


def _resolution(scene):
    percent = scene.render.resolution_percentage / 100.0
    return [int(scene.render.resolution_x * percent), int(scene.render.resolution_y * percent)]
