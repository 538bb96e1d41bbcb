"""The native render settings of a render: scene.whitted's quality and Blender's film."""

from .properties.presets import quality_of


def native_settings(native, scene, width, height, film, quality=None, shutter=0.0):
    """whitted_native.Settings for `scene` at `width` x `height` pixels.

    `film` is export.film.FilmData (border, transparent sky, pixel filter); `quality` is a
    properties.presets.Quality, by default the one scene.whitted holds; `shutter` the
    motion blur's, in frames, for the report (0: off, as in the viewport).
    """
    whitted = scene.whitted
    quality = quality or quality_of(whitted)
    settings = native.Settings(
        width=width,
        height=height,
        border=film.region,
        transparent_background=film.transparent_background,
        max_depth=quality.max_depth,
        glossy_samples=quality.glossy_samples,
        emitter_samples=quality.emitter_samples,
        aa_mode=getattr(native.AntiAliasing, quality.aa_mode),
        aa_samples=quality.aa_samples,
        aa_threshold=quality.aa_threshold,
        aa_depth=quality.aa_depth,
        adaptive_sampling=quality.adaptive_sampling,
        noise_threshold=quality.noise_threshold,
        adaptive_min_samples=quality.adaptive_min_samples,
        cutoff=quality.cutoff,
        fresnel=getattr(native.Fresnel, quality.fresnel),
        glass_shadows=getattr(native.GlassShadows, whitted.glass_shadows),
        pixel_filter=getattr(native.PixelFilterType, film.pixel_filter.type),
        filter_width=film.pixel_filter.width,
        seed=render_seed(whitted.seed, whitted.use_animated_seed, scene.frame_current),
        # Blender's thread setting (Auto = all cores, or the -t command-line value).
        threads=scene.render.threads,
        tile_size=whitted.tile_size,
        shutter=shutter,
    )
    # In waves, or with the recursive kernel (the reference): the same pixels up to float
    # rounding (native integrator/wave.h).
    settings.waves = whitted.use_waves
    # Heterogeneous media's march (native integrator/march.h), as Cycles' Volumes panel.
    settings.volume_step_rate = whitted.volume_step_rate
    settings.volume_max_steps = whitted.volume_max_steps
    return settings


def render_seed(seed, animated, frame):
    """The native seed: the scene's Seed, or with Use Animated Seed one of each frame's
    own (a hash of the frame and the seed, as Cycles'; within the native range)."""
    if not animated:
        return seed
    mixed = (frame * 0x9E3779B1 ^ seed * 0x85EBCA6B) & 0xFFFFFFFF
    mixed ^= mixed >> 16
    mixed = (mixed * 0x7FEB352D) & 0xFFFFFFFF
    return (mixed ^ (mixed >> 15)) & 0x7FFFFFFF
