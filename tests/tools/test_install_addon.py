"""scripts/install_addon.py, the development install setup.sh runs: with
BLENDER_USER_SCRIPTS and BLENDER_USER_CONFIG set (a private profile, as the test command
and a farm's workers use), it links and enables the add-on there and saves the
preferences there, never in the user's own ~/.config/blender, even where the config
folder does not exist yet (Blender 3.4 then saves in the user's own config folder where
that exists: it overwrote the user's preferences until install_addon.py made the private
folder first)."""

import os
import shutil
import subprocess
from pathlib import Path

import pytest

REPO_ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.skipif(shutil.which("blender") is None, reason="Blender 3.4 is not installed")
def test_a_private_profile_keeps_the_preferences_out_of_home(tmp_path):
    version = subprocess.run(
        ["blender", "-b", "--version"], capture_output=True, text=True, check=True
    ).stdout.split()[1]  # "Blender 3.4.1 ..."
    home = tmp_path / "home"
    # The user's own config folder exists, as on any machine Blender has run on.
    own = home / ".config" / "blender" / ".".join(version.split(".")[:2]) / "config"
    own.mkdir(parents=True)
    profile = tmp_path / "profile"
    env = dict(
        os.environ,
        HOME=str(home),
        BLENDER_USER_SCRIPTS=str(profile / "scripts"),
        BLENDER_USER_CONFIG=str(profile / "config"),  # not made yet
    )
    result = subprocess.run(
        [
            "blender",
            "-b",
            "--python-exit-code",
            "1",
            "--python",
            str(REPO_ROOT / "scripts" / "install_addon.py"),
            "--",
            str(REPO_ROOT / "addon"),
        ],
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    assert (profile / "config" / "userpref.blend").is_file()
    assert (profile / "scripts" / "addons" / "whitted").resolve() == REPO_ROOT / "addon"
    assert not list(home.rglob("userpref.blend")), "saved in HOME's ~/.config/blender"
