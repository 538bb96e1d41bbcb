"""`python -m whitted_tools`: every verb's module exists and runs its --help, the help
lists every verb with a description, an unknown verb fails; without Blender."""

import subprocess
import sys

import pytest
from whitted_tools.verbs import GROUPS, VERBS, blender_line, first_line, help_text, python_line, run


def whitted_tools(*args):
    return subprocess.run(
        [sys.executable, "-m", "whitted_tools", *args],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )


def test_help_lists_every_verb_with_its_description_by_group():
    result = whitted_tools("--help")
    assert result.returncode == 0, result.stderr
    assert result.stdout == help_text() + "\n"
    for group, verbs in GROUPS.items():
        assert f"\n{group}: {first_line(group)}" in result.stdout
        for verb, module in verbs.items():
            description = first_line(module)
            assert description, f"{module} has no docstring"
            assert f"  {verb:<{max(map(len, VERBS))}}  {description}\n" in result.stdout + "\n"


def test_an_unknown_verb_fails_and_shows_the_verbs():
    result = whitted_tools("no-such-verb")
    assert result.returncode == 1
    assert "unknown verb 'no-such-verb'" in result.stderr
    assert "bench-performance" in result.stderr


@pytest.mark.parametrize("verb", sorted(VERBS))
def test_every_verb_runs_its_help(verb):
    # The verbs that import bpy load the .venv's bpy 5.0 module for their --help.
    result = whitted_tools(verb, "--help")
    assert result.returncode == 0, result.stderr[-2000:]
    assert f"usage: python -m whitted_tools {verb}" in result.stdout


def test_the_command_lines_a_page_states():
    assert python_line("bench-memory", "--quick") == (
        ".venv/bin/python -m whitted_tools bench-memory --quick"
    )
    assert blender_line("gallery-lights", "--out", "docs") == (
        "blender -b --factory-startup --python-exit-code 1 --python "
        "tools/whitted_tools/__main__.py -- gallery-lights --out docs"
    )


def test_run_hands_the_verb_its_own_arguments(capsys):
    with pytest.raises(SystemExit) as exit_:
        run(["compare-kernels-table", "--help"])
    assert exit_.value.code == 0
    assert capsys.readouterr().out.startswith(
        "usage: python -m whitted_tools compare-kernels-table"
    )
    with pytest.raises(SystemExit):  # the verb's own parser: RESULT.json is required
        run(["compare-kernels-table"])
    assert "required: results" in capsys.readouterr().err
