"""whitted_tools.builds: two builds side by side, here the build under test twice (the
module from the build directory, as another build's folder would hold it)."""

import pytest
from conftest import BUILD_DIR
from whitted_tools.builds import SMALL, interleaved, native_module, round_order, trace_best


def test_rounds_alternate_which_build_goes_first():
    assert [round_order(index, 2) for index in range(3)] == [[0, 1], [1, 0], [0, 1]]
    calls = []

    def run(build, index):
        calls.append((index, build))
        return f"{index}:{build}"

    # Every round holds each build's result in build order, whichever ran first.
    assert interleaved(2, 2, run) == [["0:0", "0:1"], ["1:0", "1:1"]]
    assert calls == [(0, 0), (0, 1), (1, 1), (1, 0)]


def test_native_module_loads_a_builds_module_from_its_folder(tmp_path):
    module = native_module(BUILD_DIR)
    assert hasattr(module, "RenderJob")
    with pytest.raises(FileNotFoundError, match="no whitted_native module"):
        native_module(tmp_path)


def test_the_same_build_traces_the_same_scene_alike():
    first = trace_best(BUILD_DIR, SMALL, repeats=1)
    second = trace_best(BUILD_DIR, SMALL, repeats=1)
    assert first["rays"] > SMALL["width"] * SMALL["height"] * SMALL["aa_samples"] ** 2
    assert 0.0 < first["mean"] < 1.0
    assert (first["rays"], first["mean"]) == (second["rays"], second["mean"])
    assert first["trace"] > 0.0
