"""Render saved scenes with Whitted to float EXRs, inside Blender 3.4 or a bpy module,
from the development install or from a package installed into this process's
(throw-away) user profile. Run by tests/package:

    blender -b --factory-startup --python-exit-code 1 --python render_scenes.py -- ARGS
    .venv-5.2/bin/python render_scenes.py ARGS

ARGS: --scene FILE.blend FILE.exr [--scene ...] --resolution W H [--install ZIP]
      [--cycles-first] [--report FILE.json] [--keep-errors] [--volume-probe FOLDER]

Each FILE.blend is a scene saved once (by Blender 3.4, or the demo saved by the same
Blender): renders that are compared render one scene file. (Building the demo scene
again in each bpy 5.0 process is not reproducible to the last bit: a few dozen of
19,200 pixels differ between two builds, while renders of one saved file are equal.)
--keep-errors: a render that fails is recorded in the report ("errors") instead of
ending the script (the tests read what a Blender without a fitting module says).

--install installs ZIP as a user add-on (3.4) or a user extension (4.2+) and enables
it; without it the development install (`whitted`, linked by scripts/setup.sh) is
enabled. --cycles-first renders a tiny Cycles frame first, so Blender's own Embree
is loaded and used before Whitted's. --volume-probe (bpy modules: it needs the tools)
makes a Mesh to Volume object in a scene of its own, renders it with Cycles (Blender's
own OpenVDB reads and samples it), and has the module's sync read its grids, which
Blender saves into FOLDER (the module's OpenVDB reads a file Blender's wrote). The
report says which module was used and which Embree/TBB/OpenVDB files the process mapped.
"""

import argparse
import json
import os
import sys

import bpy


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else sys.argv[1:]
    parser = argparse.ArgumentParser()
    parser.add_argument("--scene", nargs=2, action="append", required=True)
    parser.add_argument("--resolution", nargs=2, type=int, default=(160, 120))
    parser.add_argument("--install")
    parser.add_argument("--cycles-first", action="store_true")
    parser.add_argument("--report")
    parser.add_argument("--keep-errors", action="store_true")
    parser.add_argument("--volume-probe")
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
    wanted = ("embree", "tbb", "openvdb", "whitted_native")
    return sorted(p for p in paths if any(name in p for name in wanted))


def cycles_frame(path):
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 1
    scene.render.resolution_x, scene.render.resolution_y = 32, 24
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)


def render(blend, output, resolution, cycles_first):
    bpy.ops.wm.open_mainfile(filepath=os.path.abspath(blend))
    scene = bpy.context.scene
    if cycles_first:
        cycles_frame(output + ".cycles.png")
    scene.render.engine = "WHITTED"
    scene.render.resolution_x, scene.render.resolution_y = resolution
    scene.render.resolution_percentage = 100
    settings = scene.render.image_settings
    if hasattr(settings, "media_type"):
        settings.media_type = "IMAGE"
    settings.file_format = "OPEN_EXR"
    settings.color_depth = "32"
    settings.exr_codec = "ZIP"
    scene.render.filepath = output
    bpy.ops.render.render(write_still=True)


def volume_probe(module, native, folder):
    """What the module read of a Mesh to Volume object Cycles rendered first (module
    docstring): its sync's report lines (none: nothing skipped), whether it is an instance
    filled by its grids, the grid's voxels, and the OpenVDB files mapped."""
    import importlib

    from whitted_tools.scenes import add_object, cube_mesh, mesh_to_volume

    scene = bpy.data.scenes.new("Volume probe")
    cube = add_object(scene, "Source", cube_mesh("Source", 2.0))
    cube.hide_render = True
    mesh_to_volume(scene, "Smoke", cube, 0.1)
    camera = add_object(scene, "Camera", bpy.data.cameras.new("Camera"), location=(0, -8, 0))
    camera.rotation_euler = (1.5708, 0.0, 0.0)
    scene.camera = camera
    scene.render.engine = "CYCLES"
    scene.cycles.samples = 1
    scene.render.resolution_x = scene.render.resolution_y = 16
    scene.render.filepath = os.path.join(folder, "cycles.png")
    bpy.ops.render.render(write_still=True, scene=scene.name)
    depsgraph = scene.view_layers[0].depsgraph
    depsgraph.update()
    frame = importlib.import_module(module + ".sync.frame").sync_frame(depsgraph, native)
    read = frame.sync._volumes.get("Smoke")
    instance = frame.sync._instances.get("Smoke")
    return {
        "warnings": [w for w in frame.warnings if "Volume object" in w],
        "rendered": instance is not None and instance.volume is not None,
        "active_voxels": read.grids[0].active_voxels if read else 0,
        "mapped": [p for p in mapped_libraries() if "openvdb" in p],
    }


def denoiser(native):
    """The module's Open Image Denoise status, and whether it denoised a noisy grey image
    in this process (its device commits beside Blender's own libraries)."""
    import numpy as np

    status = dict(native.oidn_status())
    if status["ok"]:
        noisy = np.random.default_rng(3).uniform(0.0, 1.0, (32, 32, 3)).astype(np.float32)
        normal = np.zeros_like(noisy)
        normal[..., 2] = 1.0
        clean = native.oidn_denoise(noisy, np.full_like(noisy, 0.5), normal, threads=2)
        status["denoised"] = float(np.std(clean)) < 0.5 * float(np.std(noisy))
    return status


def main():
    args = parse_args()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    module = install(os.path.abspath(args.install)) if args.install else enable_development()
    errors = {}
    for index, (blend, output) in enumerate(args.scene):
        output = os.path.abspath(output)
        try:
            render(blend, output, args.resolution, args.cycles_first and index == 0)
        except RuntimeError as error:  # the engine's ERROR report, raised by the operator
            if not args.keep_errors:
                raise
            errors[blend] = str(error)
            continue
        print(f"render_scenes: wrote {output} with {module}", flush=True)
    native = sys.modules.get(module + ".whitted_native")
    report = {
        "blender": bpy.app.version_string,
        "python": f"{sys.version_info[0]}.{sys.version_info[1]}",
        "module": module,
        "addon_file": sys.modules[module].__file__,
        "native_file": os.path.realpath(native.__file__) if native else None,
        "mapped": mapped_libraries(),
        "oidn": denoiser(native) if native else None,
        "dev_addon_loaded": "whitted" in sys.modules and module != "whitted",
        "errors": errors,
    }
    if args.volume_probe:
        report["volume"] = volume_probe(module, native, os.path.abspath(args.volume_probe))
        report["mapped"] = mapped_libraries()
    if args.report:
        with open(args.report, "w", encoding="utf-8") as out:
            json.dump(report, out, indent=1)
    if not bpy.app.binary_path:
        # A bpy module's venv has the tools (.pth); Blender 3.4's fresh profile has not.
        from whitted_tools.blender import exit_process

        exit_process(0)


main()
