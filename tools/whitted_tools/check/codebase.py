"""Files and lines per layer, with the largest file and class of each, of a git checkout.

.venv/bin/python -m whitted_tools codebase [--repo DIR] [--rev REV]

A layer is a top folder of the repository (the add-on, the native core, the bindings, the
tools, the scripts, the tests); its files are the code git tracks there (.py, .cpp, .h,
.sh, .js). A class's size is its lines from the line that opens it to its closing brace
(C++) or last statement (Python); its members are the declarations and definitions at its
own level. --rev reads the files of another commit (e.g. to compare before and after).
"""

import argparse
import ast
import re
import subprocess
from pathlib import Path

from whitted_tools.verbs import prog

LAYERS = {
    "add-on": "addon/",
    "native core": "native/src/",
    "bindings": "native/python/",
    "tools": "tools/",
    "scripts": "scripts/",
    "tests": "tests/",
}
CODE = (".py", ".cpp", ".h", ".sh", ".js")
# A class or struct definition's head, up to its opening brace (not a declaration).
CPP_CLASS = re.compile(
    r"^[ \t]*(?:template\s*<[^;{]*?>\s*)?(?P<keyword>class|struct)\s+(?P<name>\w+)[^;{()]*\{", re.M
)
ACCESS = ("public:", "private:", "protected:")


def python_classes(text):
    """(name, lines, members) of every class in a Python source."""
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.ClassDef):
            members = sum(
                isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef, ast.AnnAssign, ast.Assign))
                for n in node.body
            )
            yield node.name, node.end_lineno - node.lineno + 1, members


def cpp_classes(text):
    """(name, lines, members) of every class or struct defined in a C++ source: members
    are the statements and definitions that start at the class's own brace depth."""
    for match in CPP_CLASS.finditer(text):
        start = match.end() - 1
        depth, end = 0, start
        for end in range(start, len(text)):
            depth += {"{": 1, "}": -1}.get(text[end], 0)
            if depth == 0:
                break
        body = text[start:end].splitlines()[1:]
        members, level = 0, 0
        for line in body:
            stripped = line.strip()
            at_top = level == 0 and stripped and not stripped.startswith(("//", "}", *ACCESS))
            if at_top and stripped.endswith((";", "{")):
                members += 1
            level += line.count("{") - line.count("}")
        # From the line that names it to the line that closes it.
        lines = text.count("\n", 0, end) - text.count("\n", 0, match.start("keyword")) + 1
        yield match.group("name"), lines, members


def source(repo, rev, path):
    if rev is None:
        return (repo / path).read_text(errors="replace")
    return subprocess.run(
        ["git", "show", f"{rev}:{path}"], cwd=repo, check=True, capture_output=True, text=True
    ).stdout


def tracked(repo, rev):
    command = ["git", "ls-files"] if rev is None else ["git", "ls-tree", "-r", "--name-only", rev]
    return subprocess.run(
        command, cwd=repo, check=True, capture_output=True, text=True
    ).stdout.split()


def layer_rows(repo, rev=None):
    """One dict per layer: files, lines, the largest file and the largest class."""
    files = [f for f in tracked(repo, rev) if f.endswith(CODE)]
    rows = []
    for layer, prefix in LAYERS.items():
        sizes, classes = [], []
        for path in (f for f in files if f.startswith(prefix)):
            text = source(repo, rev, path)
            sizes.append((text.count("\n"), path))
            if path.endswith(".py"):
                classes += [
                    (lines, members, name, path) for name, lines, members in python_classes(text)
                ]
            elif path.endswith((".cpp", ".h")):
                classes += [
                    (lines, members, name, path) for name, lines, members in cpp_classes(text)
                ]
        rows.append(
            {
                "layer": layer,
                "files": len(sizes),
                "lines": sum(lines for lines, _ in sizes),
                "largest_file": max(sizes, default=(0, "-")),
                "largest_class": max(classes, default=None),
            }
        )
    return rows


def table(rows):
    lines = [
        "| layer | files | lines | largest file (lines) | largest class (lines, members) |",
        "|---|---:|---:|---|---|",
    ]
    for row in rows:
        size, path = row["largest_file"]
        cls = row["largest_class"]
        cls_cell = "-" if cls is None else f"`{cls[2]}` in `{cls[3]}` ({cls[0]}, {cls[1]})"
        lines.append(
            f"| {row['layer']} | {row['files']} | {row['lines']} | `{path}` ({size}) | {cls_cell} |"
        )
    return lines


def main(argv):
    parser = argparse.ArgumentParser(prog=prog(__name__), description=__doc__.splitlines()[0])
    parser.add_argument(
        "--repo", type=Path, default=Path.cwd(), help="a git checkout (default: here)"
    )
    parser.add_argument("--rev", help="a commit to read instead of the working tree")
    args = parser.parse_args(argv)
    print("\n".join(table(layer_rows(args.repo, args.rev))))
