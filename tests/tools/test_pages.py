"""whitted_tools.pages, cli and blender without Blender: tables, headers, number formats,
the arguments a script is given, the commands of child processes and their results."""

import sys

import pytest
from whitted_tools import REPO
from whitted_tools.blender import (
    ENTRY,
    blender_command,
    bpy_command,
    child_environment,
    run_for_json,
    verb_in_blender,
    verb_in_bpy,
    verb_in_same_blender,
)
from whitted_tools.cli import page_parser, script_args
from whitted_tools.pages import (
    command_line,
    num,
    ratio,
    ratio_text,
    seconds_text,
    table,
    write_page,
)
from whitted_tools.verbs import ENTRY_FILE


def test_table_aligns_the_first_column_left_and_numbers_right():
    assert table(["scene", "s"], [["demo", 1.5], ["glass", "—"]]) == [
        "| scene | s |",
        "|---|---:|",
        "| demo | 1.5 |",
        "| glass | — |",
    ]
    assert table(["a", "b"], [], align="ll")[1] == "|---|---|"


def test_table_refuses_a_row_of_the_wrong_width():
    with pytest.raises(ValueError, match="one entry per column"):
        table(["a", "b"], [["only one"]])


def test_command_line_names_the_checkouts_python_relative_to_it():
    venv_python = str(REPO / ".venv" / "bin" / "python")
    assert command_line("bench-memory", ["--out", "a b"], python=venv_python) == (
        ".venv/bin/python -m whitted_tools bench-memory --out 'a b'"
    )
    assert command_line("farm", [], python="/usr/bin/python3") == (
        "/usr/bin/python3 -m whitted_tools farm"
    )


def test_number_formats():
    assert num(None) == "—"
    assert num(1.23456, 2, " s") == "1.23 s"
    assert seconds_text(1.23456) == "1.235"
    assert seconds_text(12.345) == "12.3"
    assert ratio_text(None) == "—"
    assert ratio_text(2.0) == "2.00x"
    assert ratio(1.0, 0.0) is None
    assert ratio(None, 2.0) is None
    assert ratio(3.0, 2.0) == 1.5


def test_write_page_ends_with_one_newline(tmp_path):
    path = write_page(tmp_path / "docs" / "PAGE.md", ["# Title", "", "text"])
    assert path.read_text(encoding="utf-8") == "# Title\n\ntext\n"
    # A page whose sections each end with an empty line still ends with one newline.
    write_page(path, ["# Title", "", "text", "", ""])
    assert path.read_text(encoding="utf-8") == "# Title\n\ntext\n"


@pytest.mark.parametrize(
    ("argv", "expected"),
    [
        (["blender", "-b", "--python", "s.py", "--", "--out", "x"], ["--out", "x"]),
        (["/usr/bin/blender", "-b", "--python", "s.py"], []),  # Blender's own, none ours
        (["scripts/s.py", "--out", "x"], ["--out", "x"]),  # a Python running the script
        (["scripts/s.py", "--", "--out"], ["--out"]),
    ],
)
def test_script_args(argv, expected):
    assert script_args(argv) == expected


def test_a_child_blender_gets_no_colour_config_of_its_parents(monkeypatch):
    # bpy sets OCIO to its own configuration; Blender 3.4 cannot read 5.2's.
    monkeypatch.setenv("OCIO", "/bpy/5.2/datafiles/colormanagement/config.ocio")
    monkeypatch.setenv("WHITTED_KEPT", "1")
    environment = child_environment()
    assert "OCIO" not in environment and environment["WHITTED_KEPT"] == "1"


def test_blender_commands():
    assert blender_command("s.py", "--size", 4) == [
        *("blender", "-b", "--factory-startup", "--python-exit-code", "1"),
        *("--python", "s.py", "--", "--size", "4"),
    ]
    command = blender_command("s.py", blend="f.blend", addons=("whitted",))
    assert command[3:6] == ["--addons", "whitted", "f.blend"]
    assert bpy_command("s.py", "--blend", "f.blend", python="py") == [
        "py",
        "s.py",
        "--blend",
        "f.blend",
    ]


def test_page_parser_takes_out_and_the_repeats_it_is_given():
    doc = "Writes a page.\n\nMore words."
    parser = page_parser("whitted_tools.gallery.lights", doc, repeats=9)
    assert parser.prog == "python -m whitted_tools gallery-lights"
    assert parser.description == "Writes a page."
    args = parser.parse_args(["--out", "docs"])
    assert (args.out, args.repeats) == ("docs", 9)
    assert parser.parse_args(["--out", "d", "--repeats", "3"]).repeats == 3
    lights = page_parser("whitted_tools.gallery.lights", doc)
    assert not hasattr(lights.parse_args(["--out", "d"]), "repeats")
    with pytest.raises(SystemExit):
        lights.parse_args([])  # --out is required


def test_run_for_json_hands_back_what_the_child_wrote_or_why_not(tmp_path):
    out = tmp_path / "figures.json"
    write = f"import json; json.dump({{'seconds': 1.5}}, open({str(out)!r}, 'w'))"
    assert run_for_json([sys.executable, "-c", write], out, timeout=60) == ({"seconds": 1.5}, None)
    figures, problem = run_for_json([sys.executable, "-c", "raise SystemExit(3)"], out, 60)
    assert figures is None
    assert problem.startswith("failed (exit 3 after ")


def test_verbs_run_through_the_package_entry_in_blender_and_with_m_in_bpy():
    assert verb_in_blender("perf-render", "--n", 2, blend="f.blend") == blender_command(
        ENTRY, "perf-render", "--n", 2, blend="f.blend"
    )
    assert ENTRY.is_file() and ENTRY.relative_to(REPO).as_posix() == ENTRY_FILE
    assert verb_in_bpy("farm", "x", python="py") == ["py", "-m", "whitted_tools", "farm", "x"]


def test_verb_in_same_blender_runs_the_verb_in_the_blender_that_asks():
    inside = ["/opt/blender/blender", "-b", "--python", "s.py", "--", "--x"]
    assert verb_in_same_blender("bench-effects", "--n", 2, argv=inside) == verb_in_blender(
        "bench-effects", "--n", 2, blender="/opt/blender/blender"
    )
    assert verb_in_same_blender("bench-effects", "--n", 2, argv=["s.py"]) == [
        sys.executable,
        *("-m", "whitted_tools", "bench-effects", "--n", "2"),
    ]
