"""Render the demo scene with Whitted to a float EXR, inside Blender 3.4 or the bpy 5.0
module, from the development install or from a package installed into this process's
(throw-away) user profile. Run by tests/package/test_package.py:

    blender -b --factory-startup --python-exit-code 1 --python render_demo.py -- ARGS
    .venv/bin/python render_demo.py ARGS

ARGS: --blend DEMO.blend --output FILE.exr --resolution W H [--install ZIP]
      [--cycles-first] [--report FILE.json]

DEMO.blend is the demo scene saved by `scripts/demo_scene.py --save FILE --no-render`
in the same Blender: the renders compare one scene file. (Building the demo scene
again in each bpy 5.0 process is not reproducible to the last bit: a few dozen of
19,200 pixels differ between two builds, while renders of one saved file are equal.)

--install installs ZIP as a user add-on (3.4) or a user extension (4.2+) and enables
it; without it the development install (`whitted`, linked by scripts/setup.sh) is
enabled. --cycles-first renders a tiny Cycles frame first, so Blender's own Embree
is loaded and used before Whitted's. The report says which module was used and
which Embree/TBB files the process mapped.
"""

import argparse
import json
import os
import sys

import bpy


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else sys.argv[1:]
    parser = argparse.ArgumentParser()
    parser.add_argument("--blend", required=True)
    parser.add_argument("--output", required=True)
    parser.add_argument("--resolution", nargs=2, type=int, default=(160, 120))
    parser.add_argument("--install")
    parser.add_argument("--cycles-first", action="store_true")
    parser.add_argument("--report")
    return parser.parse_args(argv)


def install(zip_path):
    """Install and enable the package; returns the add-on's module name."""
    if bpy.app.version >= (4, 2, 0):
        result = bpy.ops.extensions.package_install_files(
            filepath=zip_path, repo="user_default", enable_on_install=True
        )
        module = "bl_ext.user_default.whitted"
    else:
        result = bpy.ops.preferences.addon_install(filepath=zip_path)
        assert result == {"FINISHED"}, result
        module = "whitted"
        result = bpy.ops.preferences.addon_enable(module=module)
    assert result == {"FINISHED"}, result
    assert module in bpy.context.preferences.addons, list(bpy.context.preferences.addons.keys())
    return module


def enable_development():
    import addon_utils

    assert addon_utils.enable("whitted", default_set=True) is not None
    return "whitted"


def mapped_libraries():
    with open("/proc/self/maps", encoding="utf-8") as maps:
        paths = {line.split()[-1] for line in maps if "/" in line}
    return sorted(p for p in paths if "embree" in p or "tbb" in p or "whitted_native" in p)


def cycles_frame(path):
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 1
    scene.render.resolution_x, scene.render.resolution_y = 32, 24
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)


def main():
    args = parse_args()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    module = install(os.path.abspath(args.install)) if args.install else enable_development()
    bpy.ops.wm.open_mainfile(filepath=os.path.abspath(args.blend))
    scene = bpy.context.scene
    output = os.path.abspath(args.output)
    if args.cycles_first:
        cycles_frame(output + ".cycles.png")
    scene.render.engine = "WHITTED"
    scene.render.resolution_x, scene.render.resolution_y = args.resolution
    scene.render.resolution_percentage = 100
    settings = scene.render.image_settings
    if hasattr(settings, "media_type"):
        settings.media_type = "IMAGE"
    settings.file_format = "OPEN_EXR"
    settings.color_depth = "32"
    settings.exr_codec = "ZIP"
    scene.render.filepath = output
    bpy.ops.render.render(write_still=True)
    native = sys.modules[module + ".whitted_native"]
    report = {
        "blender": bpy.app.version_string,
        "module": module,
        "addon_file": sys.modules[module].__file__,
        "native_file": os.path.realpath(native.__file__),
        "mapped": mapped_libraries(),
        "dev_addon_loaded": "whitted" in sys.modules and module != "whitted",
    }
    if args.report:
        with open(args.report, "w", encoding="utf-8") as out:
            json.dump(report, out, indent=1)
    print(f"render_demo: wrote {output} with {module}", flush=True)


main()
