"""Write the README's "Supported Blender versions" table from a test run's results.

    .venv/bin/python -m whitted_tools blender-versions [--readme README.md]

The rows are whitted_tools.blenders.BLENDERS; what each showed comes from
build/blender_versions/, which scripts/test.sh fills: LABEL-full.json (the whole
in-Blender suite, tests/blender/run.py with WHITTED_RESULTS), LABEL-package.json and
LABEL-smoke.json (tests/package/test_versions.py). The table is written between the
README's `<!-- blender-versions -->` and `<!-- /blender-versions -->` lines.
"""

import argparse
import datetime
import json
import sys

from whitted_tools import REPO
from whitted_tools.blenders import BLENDERS
from whitted_tools.verbs import prog

RESULTS = REPO / "build" / "blender_versions"
BEGIN, END = "<!-- blender-versions -->", "<!-- /blender-versions -->"


def load(label, kind):
    path = RESULTS / f"{label}-{kind}.json"
    return json.loads(path.read_text()) if path.exists() else None


def counts(record):
    """'667 passed, 8 skipped' (and what failed) from a tests/blender/run.py record."""
    order = ("passed", "failed", "error", "skipped", "xfailed", "xpassed")
    text = ", ".join(f"{record['counts'][k]} {k}" for k in order if record["counts"].get(k))
    if record["failed"]:
        text += " (" + ", ".join(record["failed"]) + ")"
    return f"{text} in {record['seconds']:.0f} s"


def shown(entry):
    """What the last run showed for one Blender, in words; "not run" without results."""
    parts = []
    full = load(entry.label, "full")
    if full:
        parts.append(f"Blender {full['blender']}: whole suite {counts(full)}")
    package = load(entry.label, "package")
    if package:
        installed = package.get("installed")
        if installed:
            parts.append(f"installed and enabled in a fresh profile ({installed['blender']})")
        for scene in ("demo", "nodes"):
            if scene in package:
                figures = package[scene]
                parts.append(
                    f"{scene}: SSIM {figures['ssim']:.3f}, luminance {figures['ratio']:.3f} "
                    "of 3.4's"
                )
    smoke = load(entry.label, "smoke")
    if smoke:
        parts.append(f"sync, passes and light linking tests: {counts(smoke)}")
    return "; ".join(parts) or "not run"


def table():
    stamps = [path.stat().st_mtime for path in RESULTS.glob("*.json")]
    when = (
        datetime.datetime.fromtimestamp(max(stamps), datetime.UTC).strftime("%Y-%m-%d")
        if stamps
        else "never"
    )
    how = {
        "full": "full: the whole in-Blender suite, and the package",
        "smoke": "smoke: the package; the sync, passes and light linking tests",
    }
    lines = [
        f"What the last run of `scripts/test.sh` showed ({when}; written by "
        "`python -m whitted_tools blender-versions` from `build/blender_versions/`):",
        "",
        "| Blender | its Python | tier | as | last run |",
        "|---|---|---|---|---|",
    ]
    for entry in BLENDERS:
        kind = f"`bpy` module (`{entry.venv}`)" if entry.is_module else "Debian's `blender`"
        lines.append(
            f"| {entry.label} | {entry.python} | {how[entry.tier]} | {kind} | {shown(entry)} |"
        )
    return "\n".join(lines)


def main(argv):
    parser = argparse.ArgumentParser(prog=prog(__name__), description=__doc__.split("\n\n")[0])
    parser.add_argument("--readme", default=str(REPO / "README.md"))
    args = parser.parse_args(argv)
    with open(args.readme, encoding="utf-8") as source:
        text = source.read()
    if BEGIN not in text or END not in text:
        sys.exit(f"{args.readme} has no {BEGIN} ... {END} lines")
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    updated = f"{head}{BEGIN}\n{table()}\n{END}{tail}"
    with open(args.readme, "w", encoding="utf-8") as out:
        out.write(updated)
    print(table())
