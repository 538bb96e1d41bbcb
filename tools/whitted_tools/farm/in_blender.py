"""The Blender side of whitted_tools farm: the render settings of a farm frame, and the
warm renderer that serves a worker frame after frame.

    blender -b SCENE -E WHITTED --python in_blender.py [-f N | -s A -e B -a] -- OUTPUT
    blender -b [-t T] --python in_blender.py -- --serve FD

With OUTPUT, the script only applies the farm's settings (float EXR to OUTPUT, no
border) and Blender's own arguments after it render: the single-machine reference of
tests/farm. With --serve, Blender starts without a scene (so a worker can start it
before the scene has arrived) and reads one JSON request per line on stdin,
{"scene": BLEND, "frame": N, "border": [xmin, ymin, xmax, ymax] or null,
"output": PATH, "stats": PATH}. It opens BLEND when it is not the file already open
(Whitted as its engine, as `-E WHITTED` would), renders that frame (the evaluated
depsgraph is rebuilt for it; the scene stays loaded, the add-on and its native module
stay loaded), writes it to PATH.exr (a still:
no '#' is replaced) and answers one JSON line, {"frame": N, "seconds": S}, on the
file descriptor FD (a pipe the worker passed; Blender's own output, its log, goes to
stdout and stderr as usual). End of input ends Blender. A Whitted failure ends the process with exit
code 3 (WHITTED_EXIT_ON_ERROR=1, which the worker sets), so a failed frame never
leaves a half-initialised renderer behind: the worker starts a fresh one.

whitted_tools farm sends this file's text to every worker (workers share no filesystem).
"""

import json
import os
import sys
import time

import bpy


def apply_settings(scene, output, border):
    """Float RGBA EXR written to `output` (Blender adds the extension, and the frame
    number for '#'), and the tile's border (fractions) when there is one."""
    render = scene.render
    settings = render.image_settings
    if hasattr(settings, "media_type"):
        settings.media_type = "IMAGE"
    settings.file_format = "OPEN_EXR"
    settings.color_depth = "32"
    settings.exr_codec = "ZIP"
    settings.color_mode = "RGBA"
    render.use_file_extension = True
    render.filepath = output
    render.use_border = border is not None
    render.use_crop_to_border = border is not None
    if border is not None:
        render.border_min_x, render.border_min_y = border[0], border[1]
        render.border_max_x, render.border_max_y = border[2], border[3]


def serve(requests, replies):
    opened = None
    for line in requests:
        request = json.loads(line)
        started = time.perf_counter()
        if request["scene"] != opened:
            bpy.ops.wm.open_mainfile(filepath=request["scene"])
            opened = request["scene"]
            # What `-E WHITTED` does for a file given on the command line.
            bpy.context.scene.render.engine = "WHITTED"
        scene = bpy.context.scene
        # The engine writes the frame's statistics (or its failure) to this file.
        os.environ["WHITTED_STATS"] = request["stats"]
        apply_settings(scene, request["output"], request["border"])
        scene.frame_set(request["frame"])
        bpy.ops.render.render(write_still=True)
        reply = {"frame": request["frame"], "seconds": time.perf_counter() - started}
        replies.write(json.dumps(reply) + "\n")
        replies.flush()


def main():
    args = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    if len(args) == 2 and args[0] == "--serve":
        with os.fdopen(int(args[1]), "w") as replies:
            serve(sys.stdin, replies)
    elif len(args) == 1:
        apply_settings(bpy.context.scene, args[0], None)
    else:
        sys.exit(f"in_blender.py: expected OUTPUT or --serve FD after '--', got {args}")


main()
