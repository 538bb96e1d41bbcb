"""Normals against Cycles (tests/blender/node_cases_surface.py): the Texture
Coordinate Normal (object space) and the Bump node's normal, rendered by Whitted
and by Cycles as an emission colour."""

import numpy as np
import pytest
from node_cases import render, set_cycles
from node_cases_surface import CASES, build_surface_scene

# float32 differences of heights a few thousandths apart (the Bump's offsets).
BOUND = 1e-3


@pytest.mark.parametrize("case", CASES, ids=lambda c: c.name)
def test_normal_matches_cycles(case, empty_scene, tmp_path, native):
    build_surface_scene(empty_scene, case)
    set_cycles(empty_scene)
    cycles = render(empty_scene, "CYCLES", str(tmp_path), case.name)
    whitted = render(empty_scene, "WHITTED", str(tmp_path), case.name)
    covered = cycles.sum(axis=-1) > 0.0  # the tilted plane leaves the top and bottom rows
    assert covered.mean() > 0.7
    # One normal over the plane (linear heights); a bump bends it away from the plane's.
    assert np.ptp(cycles[covered], axis=0).max() < 1e-4
    if case.name.startswith("bump"):
        assert not np.allclose(cycles[covered][0], (0.5, 0.5, 1.0), atol=1e-2)
    error = np.abs(whitted - cycles)[covered].max()
    print(f"\n{case.name}: max |Whitted - Cycles| = {error:.2e}")
    first = (whitted[covered][0], cycles[covered][0])
    assert error <= BOUND, f"{case.name}: Whitted {first[0]}, Cycles {first[1]}"
