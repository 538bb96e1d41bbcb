"""Denoising with Intel Open Image Denoise (native denoise/oidn.*): whether a render is
denoised and why not, its guide images, and the denoised image.

The guides are the film's Denoising Albedo and Denoising Normal passes, written as Cycles
writes its own (native integrator/passes.h, SampleRecord): along each camera path, at the
first surface that is not near-specular, its rough colours plus its emission, clamped to
[0, 1] as OIDN asks, and its shading normal (world space, which OIDN accepts as well as
camera space). A mirror, clear glass or a sharp coat passes the path on: the albedo is
then that of what is seen in it, times the tint of the branches followed (the world's
colour, clamped, where a branch leaves the scene), and Whitted's two branches at glass
each add their share. So what a mirror reflects or glass lets through is detail to keep,
not lighting to smooth.
"""

import threading
from dataclasses import dataclass, replace

import numpy as np

# The film passes of the guides.
ALBEDO_SOURCE = "denoising_albedo"
NORMAL_SOURCE = "denoising_normal"
GUIDE_SOURCES = (ALBEDO_SOURCE, NORMAL_SOURCE)


@dataclass(frozen=True)
class Denoising:
    """Whether a render is denoised, and why (as the effects report says it)."""

    on: bool
    why: str
    # The render's options (scene.whitted): which guides, prefilter and quality.
    input_passes: str = "RGB_ALBEDO_NORMAL"
    prefilter: str = "ACCURATE"
    quality: str = "HIGH"

    def decision(self):
        """The effects report's entry ({name, on, why}, as the native analysis's)."""
        return {"name": "denoising", "on": self.on, "why": self.why}


def denoising_of(scene, native, viewport=False):
    """The Denoising of a render of `scene` (the viewport's when `viewport`: the fast
    prefilter and balanced quality, as Cycles' viewport denoises by default)."""
    whitted = scene.whitted
    wanted = whitted.use_viewport_denoising if viewport else whitted.use_denoising
    if not wanted:
        return Denoising(False, "Denoise off")
    if whitted.local_model == "LECTURE":
        return Denoising(False, "Lecture local model: the seed's algorithm, as it renders")
    status = native.oidn_status()
    if not status["ok"]:
        return Denoising(False, f"Open Image Denoise unavailable: {status['report']}")
    guides = {
        "RGB": "image alone",
        "RGB_ALBEDO": "albedo",
        "RGB_ALBEDO_NORMAL": "albedo and normal",
    }[whitted.denoising_input_passes]
    version = status["version"]
    denoising = Denoising(
        True,
        f"Open Image Denoise {version // 10000}.{version // 100 % 100}.{version % 100}, {guides}",
        whitted.denoising_input_passes,
        whitted.denoising_prefilter,
        whitted.denoising_quality,
    )
    return replace(denoising, prefilter="FAST", quality="BALANCED") if viewport else denoising


def rect_of(region):
    """(x, y, width, height) of a film region (xmin, ymin, xmax, ymax)."""
    xmin, ymin, xmax, ymax = region
    return xmin, ymin, xmax - xmin, ymax - ymin


# The film pass Cycles denoises besides Combined: the Shadow Catcher pass, whose guide is
# the normal alone, with a constant albedo of 0.5 where the denoiser takes albedo (Cycles
# 3.x-5.x, integrator/denoiser_oidn.cpp: the catcher's pass "does not need albedo", and
# OIDN wants one whenever it has a normal).
CATCHER_SOURCE = "shadow_catcher"
CATCHER_ALBEDO = 0.5


def denoise(native, job, rect, denoising, threads, cancel=None, source="combined"):
    """The denoised RGBA of rectangle (x, y, w, h) of a finished `job`'s `source` (its
    Combined, or CATCHER_SOURCE), float32[w*h, 4] (w*h, 3 for the catcher): RGB from the
    denoiser, alpha the render's. `cancel`: a native DenoiseCancel that stops it
    (RuntimeError)."""
    x, y, width, height = rect
    if source == "combined":
        noisy = np.array(job.tile(x, y, width, height), dtype=np.float32)
    else:
        noisy = np.array(job.pass_tile(source, x, y, width, height), dtype=np.float32)
    shape = (height, width, 3)
    color = np.ascontiguousarray(noisy[:, :3]).reshape(shape)
    albedo = normal = None
    if denoising.input_passes != "RGB":
        if source == CATCHER_SOURCE:
            albedo = np.full(shape, CATCHER_ALBEDO, dtype=np.float32)
        else:
            albedo = job.pass_tile(ALBEDO_SOURCE, x, y, width, height).reshape(shape)
    if denoising.input_passes == "RGB_ALBEDO_NORMAL":
        normal = job.pass_tile(NORMAL_SOURCE, x, y, width, height).reshape(shape)
    clean = native.oidn_denoise(
        color,
        albedo,
        normal,
        threads=threads,
        prefilter=denoising.prefilter.lower(),
        quality=denoising.quality.lower(),
        cancel=cancel,
    )
    out = noisy.copy()
    out[:, :3] = clean.reshape(-1, 3)
    return out


class BackgroundDenoise:
    """One denoise of a finished viewport job on a Python thread, so that Blender's
    interface stays live (OIDN releases the GIL). The thread reads the job's buffers
    only, no bpy data; stop() cancels it and waits for it."""

    def __init__(self, native, job, rect, denoising, threads):
        self.rect = rect  # (x, y, w, h) of the film it denoises
        self.result = None  # float32[w*h, 4] once done
        self.error = ""
        self._cancel = native.DenoiseCancel()
        self._thread = threading.Thread(
            target=self._run,
            args=(native, job, rect, denoising, threads),
            name="whitted-denoise",
        )
        self._thread.start()

    def _run(self, native, job, rect, denoising, threads):
        try:
            self.result = denoise(native, job, rect, denoising, threads, self._cancel)
        except RuntimeError as error:  # cancelled, or the library failed on the image
            self.error = str(error)

    @property
    def done(self):
        return not self._thread.is_alive()

    def stop(self):
        self._cancel.cancel()
        self._thread.join()
