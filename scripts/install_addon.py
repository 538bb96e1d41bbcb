"""Install and enable the Whitted add-on for the current user in one Blender.

Links ADDON_DIR as `whitted` into that Blender's user add-on folder
(~/.config/blender/<version>/scripts/addons/ unless BLENDER_USER_SCRIPTS or
BLENDER_USER_CONFIG say otherwise), enables it and saves the user preferences,
keeping whatever else the user had enabled. Run by scripts/setup.sh in both
Blenders:

    blender -b --python scripts/install_addon.py -- ADDON_DIR      (Blender 3.4)
    .venv/bin/python scripts/install_addon.py ADDON_DIR            (bpy 5.0 module)

Exits non-zero, with the reason, if the add-on cannot be enabled.
"""

import os
import sys

import bpy

ADDON_MODULE = "whitted"
ENGINE_ID = "WHITTED"


def fail(message: str) -> None:
    print(f"install_addon: error: {message}", file=sys.stderr, flush=True)
    sys.exit(1)


def script_args() -> list[str]:
    # Inside the blender binary our arguments follow "--"; as a module, sys.argv is ours.
    if "--" in sys.argv:
        return sys.argv[sys.argv.index("--") + 1 :]
    return sys.argv[1:]


def running_as_module() -> bool:
    # bpy.app.binary_path is empty when Blender is imported as a Python module.
    return not bpy.app.binary_path


def link_addon(addon_dir: str) -> str:
    addons_root = bpy.utils.user_resource("SCRIPTS", path="addons", create=True)
    link = os.path.join(addons_root, ADDON_MODULE)
    if os.path.islink(link):
        if os.path.realpath(link) == os.path.realpath(addon_dir):
            return link
        print(f"install_addon: re-pointing {link} (was -> {os.readlink(link)})")
        os.remove(link)
    elif os.path.exists(link):
        fail(f"{link} exists and is not a symlink; move it away and run set-up again")
    os.symlink(addon_dir, link)
    return link


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

    if running_as_module():
        # The bpy module starts with factory preferences and ignores the user's
        # userpref.blend; read it so that saving below keeps the user's settings.
        bpy.ops.wm.read_userpref()

    import addon_utils  # Blender's own module; importable only once bpy is loaded.

    link = link_addon(addon_dir)
    # A user add-on folder made just now is not yet on sys.path: add it.
    bpy.utils.refresh_script_paths()
    addon_utils.modules_refresh()
    module = addon_utils.enable(ADDON_MODULE, default_set=True, persistent=True)
    if module is None:
        fail(f"Blender {bpy.app.version_string} could not enable '{ADDON_MODULE}' (see above)")
    if not engine_registered():
        fail(f"'{ADDON_MODULE}' is enabled but no RenderEngine '{ENGINE_ID}' is registered")
    bpy.ops.wm.save_userpref()
    print(
        f"install_addon: Blender {bpy.app.version_string}: {link} -> {addon_dir} enabled, "
        f"preferences saved in {bpy.utils.user_resource('CONFIG')}",
        flush=True,
    )


main()
