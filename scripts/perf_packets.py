"""One render on one thread, camera packets on or off, for callgrind to count what
Embree spends per camera ray: the measurements behind the packet choice
(native/src/integrator/sampler.cpp, choose_packets; docs/notes/performance_reading.md).
With `--packets compare`, the render with packets and without, pixel by pixel.

Runs inside Blender 3.4 on a saved scene (scripts/perf_scenes.py) with the add-on:

    valgrind --tool=callgrind --collect-atstart=no --toggle-collect='*RenderJob::trace*' \\
        blender -b --factory-startup --addons whitted SCENE.blend \\
        --python scripts/perf_packets.py -- --packets on [--lens 60] [--resolution 480 270] \\
        [--aa 1]

It prints the rays by type and the choice's inputs (instances in view per pixel). With
`callgrind_annotate --inclusive=yes`, a packet's cost per camera ray is rtcIntersect4's
instructions over the camera rays; a single ray's is rtcIntersect1's over all the rays
it traced (camera, reflection, refraction, cut-outs) of the render with packets off,
less the secondary rays' share at their cost in the render with packets on.

`--packets compare` renders with packets and without and prints how many pixels
differ, by how much, and where (x, y from the bottom-left, as RenderJob.inspect takes
them).

A build with the choice sends packets only where the scene suits them, so measuring
packets where it would not takes a build without it: 0160cf1 always sends them.
"""

import argparse

import bpy
from whitted_tools.cli import script_args
from whitted_tools.native_job import run_job


def parse_args():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--packets", choices=("on", "off", "compare"), required=True)
    parser.add_argument("--lens", type=float, help="the camera's focal length (mm)")
    parser.add_argument("--resolution", nargs=2, type=int, metavar=("W", "H"))
    parser.add_argument("--aa", type=int, help="anti-aliasing samples per axis")
    return parser.parse_args(script_args())


def main():
    args = parse_args()
    from whitted.native import load_native
    from whitted.sync.frame import sync_frame

    scene = bpy.context.scene
    if args.packets != "compare":  # one thread, for callgrind; the image is the same
        scene.render.threads_mode = "FIXED"
        scene.render.threads = 1
    if args.lens:
        scene.camera.data.lens = args.lens
    if args.resolution:
        scene.render.resolution_x, scene.render.resolution_y = args.resolution
    if args.aa:
        scene.whitted.aa_samples = args.aa
    native = load_native()
    frame = sync_frame(bpy.context.evaluated_depsgraph_get(), native)
    settings = frame.settings
    if args.packets == "compare":
        compare(native, frame, settings)
        return
    settings.packets = args.packets == "on"
    stats = render(native, frame, settings).stats()
    print("rays:", stats["rays"])
    for key in ("camera_packets", "visible_instances", "instances_per_pixel"):
        print(f"{key}:", stats.get(key, "(a build without the packet choice)"))


def render(native, frame, settings):
    return run_job(frame.job(native, settings))


def compare(native, frame, settings):
    import numpy as np

    settings.packets = True
    on = render(native, frame, settings).image()
    settings.packets = False
    off = render(native, frame, settings).image()
    difference = np.abs(on - off).max(axis=-1)
    rows, columns = np.nonzero(difference)
    print(f"pixels differing: {rows.size} of {difference.size}, at most {difference.max():.4g}")
    for y, x in list(zip(rows, columns, strict=True))[:10]:
        print(f"  ({x}, {y}): packets {on[y, x]}, single rays {off[y, x]}")


if __name__ == "__main__":
    main()
