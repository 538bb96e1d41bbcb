"""The docs pages: writing them, and the verbs that make the pages not made elsewhere.

Here: the command a page was made by, the machine it ran on, Markdown tables and the
number formats the tables share; write_page, which writes every page."""

import os
import platform
import sys
from pathlib import Path

from whitted_tools import REPO
from whitted_tools.cli import inside_blender_binary
from whitted_tools.verbs import blender_line, python_line


def command_line(verb, argv, python=None):
    """The verb that is making the page, with its arguments `argv`, as typed from the
    repository root: inside the Blender binary, Blender 3.4's line through the package's
    entry file; else this Python (relative when it is the checkout's .venv) `-m
    whitted_tools`."""
    if inside_blender_binary():
        return blender_line(verb, *argv)
    python = python or sys.executable
    if Path(python).is_relative_to(REPO):
        python = os.path.relpath(python, REPO)
    return python_line(verb, *argv, python=python)


def machine_lines():
    """CPU model, cores and memory from /proc, the load when the page was written."""
    cpuinfo = Path("/proc/cpuinfo").read_text().splitlines()

    def field_of(name):
        return next(
            (line.split(":", 1)[1].strip() for line in cpuinfo if line.startswith(name)), "?"
        )

    processors = sum(1 for line in cpuinfo if line.startswith("processor"))
    meminfo = Path("/proc/meminfo").read_text().split()
    memory_gib = int(meminfo[meminfo.index("MemTotal:") + 1]) / 1024 / 1024
    return [
        f"- CPU: {field_of('model name')}, {processors} logical processors "
        f"({field_of('cpu cores')} cores per package, {field_of('siblings')} siblings); "
        f"{memory_gib:.1f} GiB memory; {platform.system()} {platform.release()}",
        f"- Load average when the page was written (1, 5, 15 min): {load_text()}",
    ]


def load_text(loads=None):
    """The load average (1, 5, 15 min; default: now) as "0.52, 0.61, 0.70"."""
    return ", ".join(f"{value:.2f}" for value in (loads or os.getloadavg()))


def table(header, rows, align=None):
    """A Markdown table's lines: header cells, rows of cells (str() of each), and per
    column "l" or "r" (default: the first column left, the others right)."""
    align = align or "l" + "r" * (len(header) - 1)
    if len(align) != len(header) or any(len(row) != len(header) for row in rows):
        raise ValueError("every row and the alignment need one entry per column")
    rule = "|" + "".join("---|" if a == "l" else "---:|" for a in align)
    return [
        "| " + " | ".join(header) + " |",
        rule,
        *("| " + " | ".join(str(cell) for cell in row) + " |" for row in rows),
    ]


def write_page(path, lines):
    """Write the page's lines, making its folder, and say where: every page of docs/
    goes through here. Empty lines at the end are dropped: one newline ends the page."""
    path = Path(path).resolve()
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join(lines).rstrip("\n") + "\n", encoding="utf-8")
    print(f"wrote {path}", flush=True)
    return path


def relative_link(path, page_dir):
    """A page's link to `path` (an image), relative to the page's folder."""
    return Path(os.path.relpath(path, page_dir)).as_posix()


# --- numbers in tables ("—" where there is none) -------------------------------------


def num(value, digits=3, suffix=""):
    """A number with `digits` decimals, '—' when missing."""
    if value is None:
        return "—"
    return f"{value:.{digits}f}{suffix}"


def seconds_text(value):
    """Seconds: 3 decimals below 10 s, else 1."""
    if value is None:
        return "—"
    return f"{value:.3f}" if value < 10 else f"{value:.1f}"


def ratio_text(value):
    return "—" if value is None else f"{value:.2f}x"


def size_label(size):
    return f"{size[0]}x{size[1]}"


def scale(value, factor):
    """value * factor, None stays None."""
    return None if value is None else value * factor


def ratio(numerator, denominator):
    """numerator / denominator; None when either is missing or the denominator is 0."""
    return None if numerator is None or not denominator else numerator / denominator
