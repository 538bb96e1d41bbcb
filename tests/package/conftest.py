"""What tests/package's files share: the package zip, built once per session, and the
scenes Blender 3.4 saves and renders as every other version's reference."""

import os
import subprocess
import zipfile
from pathlib import Path

import OpenEXR
import pytest
from whitted_tools.blender import blender_command

REPO_ROOT = Path(__file__).resolve().parents[2]
VENV_PYTHON = REPO_ROOT / ".venv" / "bin" / "python"
RENDER_SCENES = Path(__file__).with_name("render_scenes.py")
SAVE_SCENES = Path(__file__).with_name("save_scenes.py")


def run(command, env=None, timeout=600):
    result = subprocess.run(
        list(map(str, command)),
        env=env,
        capture_output=True,
        text=True,
        timeout=timeout,
        check=False,
    )
    assert result.returncode == 0, (
        f"{' '.join(map(str, command))} exited {result.returncode}\n"
        f"--- stdout\n{result.stdout[-4000:]}\n--- stderr\n{result.stderr[-4000:]}"
    )
    return result.stdout


def read_exr(path):
    """float32[height, width, 4] of a single-layer RGBA EXR (rows bottom to top)."""
    with OpenEXR.File(str(path)) as exr:
        return exr.channels()["RGBA"].pixels.copy()


def build_package(dist, *pythons):
    """scripts/package.py into `dist`; `pythons`: carry only those modules."""
    command = [VENV_PYTHON, REPO_ROOT / "scripts" / "package.py", "--dist", dist]
    for python in pythons:
        command += ["--python", python]
    run(command)
    zips = list(Path(dist).iterdir())
    assert len(zips) == 1 and zips[0].suffix == ".zip", zips
    return zips[0]


@pytest.fixture(scope="session")
def package_zip(tmp_path_factory):
    return build_package(tmp_path_factory.mktemp("dist"))


@pytest.fixture(scope="session")
def extracted(package_zip, tmp_path_factory):
    folder = tmp_path_factory.mktemp("extracted")
    with zipfile.ZipFile(package_zip) as archive:
        for info in archive.infolist():
            archive.extract(info, folder)
            # zipfile drops permissions; the loader does not need x, but keep them.
            os.chmod(folder / info.filename, info.external_attr >> 16 & 0o777 or 0o644)
    return folder / "whitted"


@pytest.fixture(scope="session")
def scenes_34(tmp_path_factory):
    """{name: (scene.blend, Blender 3.4's Whitted render of it as float32 RGBA)}: the
    demo and a third-party glTF model's node graphs, saved by Blender 3.4 (the files
    every other version opens) and rendered there by the development install."""
    folder = tmp_path_factory.mktemp("scenes-3.4")
    run(blender_command(SAVE_SCENES, folder))
    blends = {path.stem: path for path in sorted(folder.glob("*.blend"))}
    assert set(blends) == {"demo", "nodes"}, blends
    command = blender_command(RENDER_SCENES, "--resolution", *SMOKE_RESOLUTION)
    for name, blend in blends.items():
        command += ["--scene", blend, folder / f"{name}.exr"]
    run(command)
    return {name: (blend, read_exr(folder / f"{name}.exr")) for name, blend in blends.items()}


SMOKE_RESOLUTION = ("160", "120")
