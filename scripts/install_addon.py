"""Install and enable the Whitted add-on for the current user in one Blender.

Links ADDON_DIR as `whitted` into that Blender's user add-on folder
(~/.config/blender/<version>/scripts/addons/ unless BLENDER_USER_SCRIPTS or
BLENDER_USER_CONFIG say otherwise), enables it and saves the user preferences,
keeping whatever else the user had enabled. Links this checkout's tool package
(tools/whitted_tools) into the add-on modules folder beside it
(scripts/addons/modules/, always on Blender's sys.path), so the scripts and tests
Blender 3.4 runs import it (the bpy module's Python has it through the .pth that
scripts/setup.sh writes). Run by scripts/setup.sh in both Blenders:

    blender -b --python scripts/install_addon.py -- ADDON_DIR      (Blender 3.4)
    .venv/bin/python scripts/install_addon.py ADDON_DIR            (bpy 5.0 module)

Exits non-zero, with the reason, if the add-on cannot be enabled.
"""

import os
import sys

import bpy

ADDON_MODULE = "whitted"
ENGINE_ID = "WHITTED"
TOOLS_PACKAGE = "whitted_tools"
TOOLS_DIR = os.path.join(
    os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "tools", TOOLS_PACKAGE
)


def fail(message: str) -> None:
    print(f"install_addon: error: {message}", file=sys.stderr, flush=True)
    sys.exit(1)


def script_args() -> list[str]:
    # Inside the blender binary our arguments follow "--"; as a module, sys.argv is ours.
    # (whitted_tools.cli has the same; this script is what makes that package importable.)
    if "--" in sys.argv:
        return sys.argv[sys.argv.index("--") + 1 :]
    return sys.argv[1:]


def running_as_module() -> bool:
    # bpy.app.binary_path is empty when Blender is imported as a Python module.
    return not bpy.app.binary_path


def link(target: str, folder: str, name: str) -> str:
    """A symlink folder/name -> target (re-pointed if it pointed elsewhere)."""
    path = os.path.join(bpy.utils.user_resource("SCRIPTS", path=folder, create=True), name)
    if os.path.islink(path):
        if os.path.realpath(path) == os.path.realpath(target):
            return path
        print(f"install_addon: re-pointing {path} (was -> {os.readlink(path)})")
        os.remove(path)
    elif os.path.exists(path):
        fail(f"{path} exists and is not a symlink; move it away and run set-up again")
    os.symlink(target, path)
    return path


def engine_registered() -> bool:
    # Some built-in engines (HydraRenderEngine in 5.0) have no bl_idname.
    engines = bpy.types.RenderEngine.__subclasses__()
    return ENGINE_ID in {getattr(engine, "bl_idname", None) for engine in engines}


def main() -> None:
    args = script_args()
    if len(args) != 1:
        fail("usage: install_addon.py ADDON_DIR")
    addon_dir = os.path.abspath(args[0])
    if not os.path.isfile(os.path.join(addon_dir, "__init__.py")):
        fail(f"{addon_dir} is not an add-on (no __init__.py)")

    userpref = os.path.join(bpy.utils.user_resource("CONFIG"), "userpref.blend")
    # bpy 4.2's read_userpref crashes (a segmentation fault, with or without the file):
    # there the add-on is linked and checked but the preferences are left alone, so
    # nothing the user saved is overwritten (scripts enable it with addon_utils).
    keep_preferences = not running_as_module() or bpy.app.version >= (4, 3, 0)
    if running_as_module() and keep_preferences and os.path.exists(userpref):
        # The bpy module starts with factory preferences and ignores the user's
        # userpref.blend; read it so that saving below keeps the user's settings.
        bpy.ops.wm.read_userpref()

    import addon_utils  # Blender's own module; importable only once bpy is loaded.

    addon_link = link(addon_dir, "addons", ADDON_MODULE)
    if not running_as_module():  # the .venv's Python has it through setup.sh's .pth
        link(TOOLS_DIR, os.path.join("addons", "modules"), TOOLS_PACKAGE)
    # A user add-on folder made just now is not yet on sys.path: add it.
    bpy.utils.refresh_script_paths()
    addon_utils.modules_refresh()
    module = addon_utils.enable(ADDON_MODULE, default_set=True, persistent=True)
    if module is None:
        fail(f"Blender {bpy.app.version_string} could not enable '{ADDON_MODULE}' (see above)")
    if not engine_registered():
        fail(f"'{ADDON_MODULE}' is enabled but no RenderEngine '{ENGINE_ID}' is registered")
    if keep_preferences:
        # Blender saves where BLENDER_USER_CONFIG points only if that folder exists;
        # otherwise it falls back to ~/.config/blender and overwrites the user's own.
        os.makedirs(os.path.dirname(userpref), exist_ok=True)
        bpy.ops.wm.save_userpref()
        if not os.path.isfile(userpref):
            fail(f"Blender {bpy.app.version_string} did not save its preferences in {userpref}")
        saved = f"preferences saved in {bpy.utils.user_resource('CONFIG')}"
    else:
        saved = "preferences not saved (enable it with addon_utils.enable)"
    print(
        f"install_addon: Blender {bpy.app.version_string}: {addon_link} -> {addon_dir} "
        f"enabled, {saved}",
        flush=True,
    )
    if running_as_module():  # the .venv's Python has the tools through setup.sh's .pth
        from whitted_tools.blender import exit_process

        exit_process(0)


main()
