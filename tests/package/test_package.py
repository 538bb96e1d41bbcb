"""The installable package (scripts/package.py): what its compiled modules need, that
each loads with the system's Embree, TBB and OpenVDB hidden in its own CPython (and
reads an OpenVDB file there), and that it
installs into fresh user profiles of Blender 3.4 and the bpy 5.2 module and renders
the demo exactly as the development install does (tests/package/test_versions.py:
the other versions).

    .venv/bin/python -m pytest tests/package -q

Builds the zip into a temporary folder (dist/ is left alone); needs scripts/setup.sh
to have run (the build, the development install). The hidden-library check runs
in a private mount namespace (`unshare -m`): as root, or through `sudo -n`.
"""

import json
import os
import re
import subprocess
import textwrap
import zipfile

import numpy as np
import pytest
from conftest import RENDER_SCENES, REPO_ROOT, read_exr, run
from whitted_tools.blender import blender_command, bpy_command
from whitted_tools.blenders import MODULE_PYTHONS, blender
from whitted_tools.cli import load_script

RESOLUTION = ("160", "120")
SYSTEM_PYTHON = "/usr/bin/python3"

BASE_SYSTEM_LIBRARIES = load_script("package").BASE_SYSTEM_LIBRARIES


def elf_files(package_dir):
    return sorted(
        p for p in package_dir.rglob("*") if p.is_file() and p.read_bytes()[:4] == b"\x7fELF"
    )


def dynamic_section(path):
    output = run(["readelf", "-d", "-W", str(path)])
    needed = re.findall(r"\(NEEDED\)\s+Shared library: \[([^\]]+)\]", output)
    runpath = re.findall(r"\((?:RUNPATH|RPATH)\)\s+Library (?:runpath|rpath): \[([^\]]+)\]", output)
    soname = re.findall(r"\(SONAME\)\s+Library soname: \[([^\]]+)\]", output)
    return needed, runpath, soname


def test_zip_layout(package_zip):
    names = zipfile.ZipFile(package_zip).namelist()
    assert {name.split("/")[0] for name in names} == {"whitted"}
    for required in ("whitted/__init__.py", "whitted/blender_manifest.toml", "whitted/LICENSE"):
        assert required in names
    modules = [name for name in names if re.fullmatch(r"whitted/whitted_native.*\.so", name)]
    # One module per CPython a supported Blender embeds, and the libraries once.
    tags = [python.replace(".", "") for python in MODULE_PYTHONS]
    assert modules == [f"whitted/whitted_native.cpython-{t}-x86_64-linux-gnu.so" for t in tags]
    libembree = [name for name in names if "libembree3" in name and name.endswith(".so.3")]
    assert len(libembree) == 1, libembree
    # OpenVDB for Volume objects' grids, once, with Debian's copyright file beside it.
    libopenvdb = [
        n for n in names if re.fullmatch(r"whitted/libs/libopenvdb-[0-9a-f]{8}\.so\.10\.0", n)
    ]
    assert len(libopenvdb) == 1, libopenvdb
    # Every library bundled from Debian (named by its hash) has its copyright file.
    for name in names:
        if re.fullmatch(r"whitted/libs/lib.+-[0-9a-f]{8}\.so[.0-9]*", name):
            assert name.split(".so")[0] + ".copyright" in names, name
    # Open Image Denoise (scripts/stage_oidn.sh stages it for the build), with its licence,
    # and the notice of the Hosek/Wilkie sky dataset compiled into the module.
    for name in ("libOpenImageDenoise.so.2", "OpenImageDenoise.LICENSE", "HosekWilkie.LICENSE"):
        assert f"whitted/libs/{name}" in names, name
    assert not [name for name in names if "__pycache__" in name or name.endswith(".pyc")]


def test_every_library_need_is_bundled_or_base_system(extracted):
    """readelf's DT_NEEDED of every ELF file in the package: each is a file in
    whitted/libs/ or one of the base system's libraries."""
    bundled = {p.name for p in (extracted / "libs").iterdir()}
    lines = []
    for path in elf_files(extracted):
        needed, runpath, soname = dynamic_section(path)
        lines.append(f"{path.relative_to(extracted)}  SONAME={soname} RUNPATH={runpath}")
        for name in needed:
            where = (
                "bundled"
                if name in bundled
                else "base"
                if name in BASE_SYSTEM_LIBRARIES
                else "MISSING"
            )
            lines.append(f"    NEEDED {name:32s} {where}")
            assert where != "MISSING", f"{path.name} needs {name}: neither bundled nor base system"
        expected = "$ORIGIN/libs" if path.parent == extracted else "$ORIGIN"
        assert runpath == [expected], (path, runpath)
        if path.parent != extracted:
            assert soname == [path.name], "a bundled library's SONAME is its unique file name"
    print("\n".join(lines))
    # Embree, TBB, OpenVDB and OpenVDB's own needs are in there, under names nothing
    # else on a system uses.
    assert any(re.fullmatch(r"libembree3-[0-9a-f]{8}\.so\.3", n) for n in bundled)
    assert any(re.fullmatch(r"libtbb-[0-9a-f]{8}\.so\.12", n) for n in bundled)
    for stem in OPENVDB_STACK:
        assert any(n.startswith(stem.split(".so")[0] + "-") for n in bundled), stem


def _system_library(name):
    for line in run(["ldconfig", "-p"]).splitlines():
        if line.strip().startswith(name + " ") and "x86-64" in line:
            return os.path.realpath(line.split("=>")[1].strip())
    pytest.fail(f"{name} is not installed on this machine (setup installs it for the build)")


# OpenVDB and the libraries it needs that a base system lacks (Debian 12's 10.0.1).
OPENVDB_STACK = (
    "libopenvdb.so.10.0",
    "libblosc.so.1",
    "libboost_iostreams.so.1.74.0",
    "libImath-3_1.so.29",
    "liblog4cplus-2.0.so.3",
)

# A grid of 2 voxels written by OpenVDB's own Python module (python3-openvdb).
WRITE_VDB = textwrap.dedent(
    """
    import sys
    import pyopenvdb as vdb
    grid = vdb.FloatGrid()
    grid.name = "density"
    grid.getAccessor().setValueOn((0, 0, 0), 1.0)
    grid.getAccessor().setValueOn((1, 0, 0), 3.0)
    vdb.write(sys.argv[1], grids=[grid])
    """
)

HIDDEN_CHECK = textwrap.dedent(
    """
    import ctypes, importlib.util, json, subprocess, sys
    package, module_file, vdb_file = sys.argv[1], sys.argv[2], sys.argv[3]
    # The system's Embree, TBB and OpenVDB are hidden: loading them by name fails.
    for name in ("libembree3.so.3", "libtbb.so.12", "libopenvdb.so.10.0"):
        try:
            ctypes.CDLL(name)
        except OSError as error:
            print(f"hidden: {name}: {error}")
        else:
            sys.exit(f"{name} still loads: the namespace does not hide it")
    print(subprocess.run(["ldd", module_file], capture_output=True, text=True).stdout)
    spec = importlib.util.spec_from_file_location("whitted_native", module_file)
    native = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(native)
    import numpy as np
    scene = native.Scene()
    positions = np.array([[-1, -1, -3], [1, -1, -3], [0, 1, -3]], np.float32)
    scene.set_mesh("tri", positions, np.array([[0, 1, 2]], np.uint32))
    scene.set_material("m", native.Material(diffuse=(0.8, 0.8, 0.8)))
    scene.set_instance("tri", "tri", np.eye(4, dtype=np.float32), ["m"])
    scene.set_light("sun", native.Light(type=native.LightType.SUN, color=(3, 3, 3),
                                        direction=(0, 0, -1)))
    job = native.RenderJob(scene, native.Settings(width=32, height=32, threads=2),
                           camera=native.Camera())
    job.start()
    while not job.wait(1.0):
        pass
    image = job.image()
    (grid,) = native.read_volume_grids(vdb_file, ["density"])
    maps = sorted({l.split()[-1] for l in open("/proc/self/maps")
                   if any(n in l for n in ("embree", "tbb", "openvdb", "blosc", "Imath"))})
    print(json.dumps({"mean": float(image[..., :3].mean()), "voxels": grid.active_voxels,
                      "maps": maps}))
    """
)


def _namespace_prefix():
    if os.geteuid() == 0:
        return ["unshare", "-m"]
    return ["sudo", "-n", "unshare", "-m"]


def built_pythons():
    """{"3.11": interpreter, ...}: the interpreters the build made a module for (the
    CMake cache's WHITTED_PYTHON_EXECUTABLES, which scripts/setup.sh sets)."""
    cache = (REPO_ROOT / "build" / "CMakeCache.txt").read_text()
    line = re.search(r"^WHITTED_PYTHON_EXECUTABLES:STRING=(.*)$", cache, re.M).group(1)
    found = {}
    for interpreter in line.split(";"):
        version = run([interpreter, "-c", "import sys; print(*sys.version_info[:2], sep='.')"])
        found[version.strip()] = interpreter
    return found


@pytest.fixture(scope="session")
def numpy_pythons(tmp_path_factory):
    """{"3.10": python, ...}: for each CPython the package carries, an interpreter of
    it that has numpy (a throw-away venv where the build's own has none)."""
    pythons = {}
    for version, interpreter in built_pythons().items():
        has_numpy = subprocess.run(
            [interpreter, "-c", "import numpy"], capture_output=True, check=False
        ).returncode
        if has_numpy == 0:
            pythons[version] = interpreter
            continue
        venv = tmp_path_factory.mktemp(f"numpy-{version}")
        run([interpreter, "-m", "venv", venv])
        run([venv / "bin" / "python", "-m", "pip", "install", "-q", "numpy"])
        pythons[version] = str(venv / "bin" / "python")
    assert sorted(pythons) == sorted(MODULE_PYTHONS), pythons
    return pythons


@pytest.mark.parametrize("python", MODULE_PYTHONS)
def test_module_loads_with_system_embree_and_tbb_hidden(python, extracted, numpy_pythons, tmp_path):
    """In a private mount namespace the system's Embree, TBB and OpenVDB files (and
    OpenVDB's needs) are replaced by /dev/null (so any attempt to load them fails); a
    plain CPython of each version the package carries (no Blender, nothing else
    preloaded) imports the packaged module of its own ABI, renders a triangle and reads
    an OpenVDB file's grid."""
    tag = python.replace(".", "")
    module_file = next(extracted.glob(f"whitted_native.cpython-{tag}-*.so"))
    names = ("libembree3.so.3", "libtbb.so.12", "libtbbmalloc.so.2", *OPENVDB_STACK)
    hidden = [_system_library(n) for n in names]
    vdb_file = tmp_path / "two.vdb"
    run([SYSTEM_PYTHON, "-c", WRITE_VDB, vdb_file])
    script = tmp_path / "check.py"
    script.write_text(HIDDEN_CHECK)
    mounts = " && ".join(f"mount --bind /dev/null {path}" for path in hidden)
    check = f"exec {numpy_pythons[python]} {script} {extracted} {module_file} {vdb_file}"
    shell = f"mount --make-rprivate / && {mounts} && {check}"
    output = run([*_namespace_prefix(), "sh", "-c", shell])
    print(output)
    result = json.loads(output.strip().splitlines()[-1])
    assert result["mean"] > 0.0, "the triangle rendered black"
    assert result["voxels"] == 2, result
    assert result["maps"], "no Embree or TBB mapped at all?"
    for path in result["maps"]:
        assert path.startswith(str(extracted / "libs")), f"{path} is not the package's own"
    ldd = output.split("{")[0]
    for line in ldd.splitlines():
        if "=>" in line and any(n in line for n in ("embree", "tbb", "openvdb", "blosc")):
            assert str(extracted / "libs") in line, line


def _render(command, env, blend, output, report):
    run(
        [
            *command,
            "--scene",
            blend,
            output,
            "--resolution",
            *RESOLUTION,
            "--report",
            report,
        ],
        env=env,
    )
    return read_exr(output), json.loads(report.read_text())


@pytest.mark.parametrize("label", ["3.4", "5.2"])
def test_installed_package_renders_like_the_development_install(label, package_zip, tmp_path):
    """Blender 3.4 (add-on, legacy install) and bpy 5.2 (extension): the package's
    render of the demo is the development install's to the bit."""
    entry = blender(label)
    demo = REPO_ROOT / "scripts" / "demo_scene.py"
    blend = tmp_path / "demo.blend"
    if entry.is_module:
        command = bpy_command(RENDER_SCENES, python=entry.venv_python)
        run(bpy_command(demo, "--save", blend, "--no-render", python=entry.venv_python))
    else:
        command = blender_command(RENDER_SCENES)
        run(blender_command(demo, "--save", blend, "--no-render"))
    reference, dev = _render(
        command, dict(os.environ), blend, tmp_path / "dev.exr", tmp_path / "dev.json"
    )
    assert dev["native_file"].startswith(str(REPO_ROOT / "addon")), dev

    profile = tmp_path / "profile"
    env = dict(os.environ)
    if entry.is_module:
        env["BLENDER_USER_RESOURCES"] = str(profile)
        # Blender's Cycles (Embree 4, Blender's TBB) renders first in the same process.
        extra = ["--install", str(package_zip), "--cycles-first"]
    else:
        env.update(
            BLENDER_USER_SCRIPTS=str(profile / "scripts"),
            BLENDER_USER_CONFIG=str(profile / "config"),
        )
        extra = ["--install", str(package_zip)]
    pixels, installed = _render(
        [*command, *extra], env, blend, tmp_path / "pkg.exr", tmp_path / "pkg.json"
    )
    print(json.dumps(installed, indent=1))
    assert installed["native_file"].startswith(str(profile)), installed
    assert not installed["dev_addon_loaded"], "the development add-on was imported too"
    # The package's own Open Image Denoise denoises in this Blender's process.
    oidn = installed["oidn"]
    assert oidn["ok"] and oidn["denoised"], oidn
    assert oidn["path"].startswith(str(profile)), oidn
    if entry.is_module:
        assert installed["module"] == "bl_ext.user_default.whitted"
        mapped = installed["mapped"]
        assert any(p.endswith("libembree4.so.4") for p in mapped), "Cycles did not load Embree 4"
        ours = [p for p in mapped if "libembree3" in p or "libtbb-" in p]
        assert ours and all(p.startswith(str(profile)) for p in ours), mapped
        assert not [p for p in mapped if p.startswith(("/usr/lib", "/lib"))], mapped
    assert pixels.shape == reference.shape
    assert np.array_equal(pixels.view(np.uint32), reference.view(np.uint32)), (
        f"max difference {np.abs(pixels - reference).max()}"
    )
