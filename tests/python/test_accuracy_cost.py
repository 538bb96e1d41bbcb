"""The cost report end to end on a tiny scene: whitted_tools accuracy-cost drives
Blender 3.4 headless (the `blender` on PATH, as scripts/setup.sh installs it)
and writes the Markdown page and its plots with finite numbers."""

import math
import re
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def run(command):
    result = subprocess.run(command, capture_output=True, text=True, check=False, timeout=120)
    assert result.returncode == 0, f"{command}\n{result.stdout[-3000:]}\n{result.stderr[-3000:]}"


def test_report_on_a_tiny_scene(tmp_path):
    blend = tmp_path / "demo.blend"
    run(
        [
            "blender",
            "-b",
            "--factory-startup",
            "--python",
            str(REPO / "scripts" / "demo_scene.py"),
            "--",
            "--save",
            str(blend),
            "--no-render",
        ]
    )
    page = tmp_path / "docs" / "COST.md"
    notes = tmp_path / "notes.md"
    notes.write_text("A hand-written reading.\n")
    run(
        [
            sys.executable,
            *("-m", "whitted_tools", "accuracy-cost"),
            str(blend),
            "--out",
            str(page),
            "--resolution",
            "24",
            "18",
            "--repeats",
            "1",
            "--notes",
            str(notes),
        ]
    )
    text = page.read_text()
    assert "A hand-written reading." in text
    assert "## demo" in text
    images = re.findall(r"!\[[^]]*\]\(([^)]+)\)", text)
    assert len(images) == 3
    for image in images:
        png = page.parent / image
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # Every run's row: time, rays, rays/px, samples/px, RMSE, PSNR, relMSE.
    rows = [
        line
        for line in text.splitlines()
        if re.match(r"\| [^-|][^|]* \| \d", line) and line.count("|") == 9
    ]
    tables = text.count("| setting | time (s) |")
    assert tables == 14  # thirteen controls (the denoiser, the volume step rate) and the presets
    assert len(rows) >= 40
    for row in rows:
        cells = [cell.strip().replace(",", "") for cell in row.strip("|").split("|")[1:]]
        numbers = [float(cell) for cell in cells]
        reference = "(reference)" in row
        for number in numbers:
            assert math.isfinite(number) or (reference and number == math.inf), row
        assert numbers[0] > 0.0 and numbers[1] > 0.0  # a time and rays
