"""Starting Blender 3.4 and the bpy 5.0 module, and what a script inside them needs first.

The command lists are plain data (tested without Blender); enable_addon imports
Blender's addon_utils when called, so this module imports anywhere.
"""

import json
import os
import shlex
import signal
import subprocess
import sys
import time
from pathlib import Path

from whitted_tools import REPO
from whitted_tools.cli import inside_blender_binary

VENV_PYTHON = REPO / ".venv" / "bin" / "python"
ADDON = "whitted"
ENTRY = REPO / "tools" / "whitted_tools" / "__main__.py"


def blender_command(script, *args, blend=None, addons=(), blender="blender"):
    """`blender -b --factory-startup [--addons A,B] [BLEND] --python-exit-code 1
    --python SCRIPT -- ARGS`: Blender 3.4 in the background, without the user's
    preferences, ending with exit code 1 if the script raises."""
    command = [blender, "-b", "--factory-startup"]
    if addons:
        command += ["--addons", ",".join(addons)]
    if blend is not None:
        command.append(str(blend))
    command += ["--python-exit-code", "1", "--python", str(script), "--"]
    return [*command, *map(str, args)]


def child_environment():
    """The environment for a Blender started from inside another (a bpy module's tests
    running Blender 3.4): Python's view of it, without OCIO. Blender sets OCIO at the C
    level to its own colour configuration, which a child process inherits unless given
    an environment, and Blender 3.4's OpenColorIO 2.1 cannot read bpy 5.2's (version
    2.5: the child exits at start-up)."""
    return {key: value for key, value in os.environ.items() if key != "OCIO"}


def verb_in_blender(verb, *args, blend=None, addons=(), blender="blender"):
    """blender_command of the tool package's entry file: the verb VERB (whitted_tools.verbs)
    with ARGS in Blender 3.4, which imports the package through its add-on modules link."""
    return blender_command(ENTRY, verb, *args, blend=blend, addons=addons, blender=blender)


def verb_in_bpy(verb, *args, python=None):
    """The verb run by the .venv's Python (or `python`), where Blender is the bpy module:
    `PYTHON -m whitted_tools VERB ARGS`."""
    return [str(python or VENV_PYTHON), "-m", "whitted_tools", verb, *map(str, args)]


def bpy_command(script, *args, python=None):
    """The same script run by the .venv's Python, where Blender 5.0 is the bpy module
    (the script opens any .blend itself)."""
    return [str(python or VENV_PYTHON), str(script), *map(str, args)]


def addon_env(addon_dir, root):
    """The environment (os.environ's, with BLENDER_USER_SCRIPTS) of a Blender 3.4 whose
    user scripts folder, made under `root`, holds the add-on in `addon_dir` (a folder
    with its whitted_native*.so: another build of the add-on) as `whitted` and this
    checkout's tool package, as scripts/install_addon.py links them into the user's."""
    scripts = Path(root) / "scripts"
    links = {
        scripts / "addons" / ADDON: Path(addon_dir).resolve(),
        scripts / "addons" / "modules" / "whitted_tools": REPO / "tools" / "whitted_tools",
    }
    for link, target in links.items():
        link.parent.mkdir(parents=True, exist_ok=True)
        if not link.is_symlink():
            link.symlink_to(target, target_is_directory=True)
    return {**os.environ, "BLENDER_USER_SCRIPTS": str(scripts)}


def run_process(command, timeout, env=None):
    """(output, None) or (None, why it failed): stdout and stderr together. A process
    past its timeout is killed with its process group (POV-Ray runs as Blender's
    child); `timeout` None waits for it however long it takes. `env`: the process's
    environment (default: this one's)."""
    print(f"  $ {shlex.join(map(str, command))}", flush=True)
    started = time.perf_counter()
    with subprocess.Popen(
        list(map(str, command)),
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        errors="replace",
        start_new_session=True,
        env=env,
    ) as process:
        try:
            output, _ = process.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            process.communicate()
            return None, f"timed out after {timeout:.0f} s"
    seconds = time.perf_counter() - started
    if process.returncode != 0:
        return None, failure(process.returncode, seconds, output)
    return output, None


def run_for_json(command, json_path, timeout, env=None):
    """(the JSON the process wrote to json_path, None) or (None, why it failed): a
    child that measures something and hands its figures back in a file."""
    _, problem = run_process(command, timeout, env=env)
    if problem:
        return None, problem
    return json.loads(Path(json_path).read_text(encoding="utf-8")), None


def verb_in_same_blender(verb, *args, argv=None):
    """The command that runs the verb in the Blender this process is (`argv`: its
    sys.argv): the Blender binary that runs it, or this Python with the bpy module."""
    argv = sys.argv if argv is None else argv
    if inside_blender_binary(argv):
        return verb_in_blender(verb, *args, blender=argv[0])
    return verb_in_bpy(verb, *args, python=sys.executable)


def failure(returncode, seconds, output):
    """Why a process failed, in one line: its exit code, time and last lines."""
    tail = " / ".join(line for line in output.splitlines()[-4:] if line.strip())
    return f"failed (exit {returncode} after {seconds:.0f} s): {tail[-300:]}"


def addon_problem(module=ADDON):
    """Enables the add-on `module` (and keeps it enabled after a factory reset's
    re-enable); None, or why it cannot be."""
    # Blender's own module; as the bpy module, importable only once bpy is loaded.
    import addon_utils

    if addon_utils.enable(module, default_set=True) is not None:
        return None
    if module == ADDON:
        return (
            f"cannot enable the add-on '{ADDON}': run scripts/setup.sh, which links addon/ "
            "into Blender's user add-on folder (addon_utils looked in: "
            f"{', '.join(addon_utils.paths())})"
        )
    return f"cannot enable Blender's add-on '{module}'"


def enable_addon(*modules):
    """Enables each add-on (default: Whitted) or ends the script saying why not."""
    for module in modules or (ADDON,):
        problem = addon_problem(module)
        if problem:
            sys.exit(f"{Path(sys.argv[0]).name}: {problem}")


def exit_process(code=0):
    """End this Blender process with exit code `code`.

    bpy 4.2 as a Python module crashes when its interpreter exits once an add-on has
    registered classes, even after unregistering them (a segmentation fault: Blender's
    SpaceType destructor, run by exit(), frees a Python class after the interpreter
    has finished; seen with bpy 4.2.23, not with 4.5 and later). There the process
    ends at once, its output flushed, so the exit code is the script's own."""
    import bpy

    if not bpy.app.binary_path and bpy.app.version < (4, 3, 0):
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)
    sys.exit(code)


# The Whitted settings the tools' scenes and the tests' expectations were made with: a
# new scene's before issue 46 (2 x 2 regular samples, 4 x 4 feelers per sized lamp, the
# native defaults elsewhere, no noise threshold, no denoising, each pixel its own square
# (a Box filter, not Cycles' Blackman-Harris 1.5)). A new scene now starts
# at the Final preset (addon/properties/presets.py NEW_SCENE); scripts and tests that
# measure something else than that keep these, so their figures stay comparable.
SEED_QUALITY = {
    "max_depth": 5,
    "aa_mode": "REGULAR",
    "aa_samples": 2,
    "aa_threshold": 0.3,
    "aa_depth": 3,
    "adaptive_sampling": False,
    "light_samples": 4,
    "glossy_samples": 2,
    "emitter_samples": 2,
    "fresnel": "EXACT",
    "cutoff": 1.0 / 255.0,
    "texture_filter": "AUTHORED",
    "use_denoising": False,
    "pixel_filter_type": "BOX",
}


def seed_quality(scene):
    """Set `scene`'s Whitted settings to SEED_QUALITY."""
    for name, value in SEED_QUALITY.items():
        setattr(scene.whitted, name, value)


def factory_scene(*modules):
    """An empty factory scene with the add-ons enabled (default: Whitted) and Whitted's
    SEED_QUALITY: the start of every scene a script builds (a factory reset also
    disables add-ons)."""
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    enable_addon(*modules)
    scene = bpy.context.scene
    seed_quality(scene)
    return scene
