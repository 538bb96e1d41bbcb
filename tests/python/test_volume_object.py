"""The Volume object binding (native/python/volume_object.cpp): grids that OpenVDB's own
Python module (Debian's python3-openvdb, under the system's /usr/bin/python3) writes,
listed, read, placed in the world and sampled; files that cannot be read raise
VolumeFileError with the reason."""

import subprocess
import textwrap

import numpy as np
import pytest
import whitted_native as wn

SYSTEM_PYTHON = "/usr/bin/python3"

# Two voxels of density 1 and 3 side by side in x, voxels of 0.5 units; a colour block
# of 8^3 voxels; a bool grid Whitted does not read.
WRITE = textwrap.dedent(
    """
    import sys
    import pyopenvdb as vdb
    density = vdb.FloatGrid()
    density.name = "density"
    density.transform = vdb.createLinearTransform(voxelSize=0.5)
    accessor = density.getAccessor()
    accessor.setValueOn((0, 0, 0), 1.0)
    accessor.setValueOn((1, 0, 0), 3.0)
    color = vdb.Vec3SGrid()
    color.name = "color"
    color.transform = vdb.createLinearTransform(voxelSize=0.5)
    color.fill((0, 0, 0), (7, 7, 7), (0.2, 0.4, 0.8), True)
    mask = vdb.BoolGrid()
    mask.name = "mask"
    mask.getAccessor().setValueOn((0, 0, 0), True)
    vdb.write(sys.argv[1], grids=[density, color, mask])
    """
)


@pytest.fixture(scope="module")
def vdb_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("vdb") / "grids.vdb"
    result = subprocess.run(
        [SYSTEM_PYTHON, "-c", WRITE, str(path)], capture_output=True, text=True, check=False
    )
    if "No module named 'pyopenvdb'" in result.stderr:
        pytest.fail("python3-openvdb is not installed (scripts/setup.sh installs it)")
    assert result.returncode == 0, result.stderr
    return str(path)


def test_the_module_reads_with_openvdb_10():
    assert wn.OPENVDB_VERSION.startswith("10."), wn.OPENVDB_VERSION


def test_a_files_grids_are_listed_with_their_types(vdb_file):
    # In the file's order, which pyopenvdb's write does not keep: compared sorted.
    assert sorted(wn.vdb_grids(vdb_file)) == [
        ("color", "vec3s", True),
        ("density", "float", True),
        ("mask", "bool", False),
    ]


def test_grids_are_read_sampled_and_placed(vdb_file):
    density, color = wn.read_volume_grids(vdb_file, ["density", "color"])
    assert (density.name, density.channels, density.active_voxels) == ("density", 1, 2)
    assert density.resolution == (2, 1, 1)
    assert np.allclose(density.index_to_object, np.diag([0.5, 0.5, 0.5, 1.0]))
    lower, upper = density.object_bounds
    assert np.allclose(lower, (0, 0, 0)) and np.allclose(upper, (1.0, 0.5, 0.5))
    assert density.voxel(1, 0, 0) == (3.0, 3.0, 3.0)
    # Voxel values at voxel centres (i + 0.5): halfway between the two, their mean.
    assert density.sample((1.0, 0.5, 0.5))[0] == pytest.approx(2.0)
    assert color.channels == 3 and color.resolution == (8, 8, 8)
    to_world = np.eye(4)
    to_world[:3, 3] = (10.0, 0.0, 0.0)  # the object moved by 10 in x
    volume = wn.VolumeObject(to_world, density=density, color=color)
    # Voxel 0's centre: index 0.5 -> object 0.25 -> world 10.25.
    sample = volume.sample((10.25, 0.25, 0.25))
    assert sample["density"] == pytest.approx(1.0)
    assert sample["color"] == pytest.approx((0.2, 0.4, 0.8))
    assert sample["temperature"] == 1.0 and sample["flame"] == 0.0  # no grids: their defaults
    assert volume.sample((10.5, 0.25, 0.25))["density"] == pytest.approx(2.0)
    assert volume.sample((0.0, 0.0, 0.0))["density"] == 0.0
    lower, upper = volume.world_bounds
    assert np.allclose(lower, (10.0, 0.0, 0.0)) and np.allclose(upper, (14.0, 4.0, 4.0))
    assert volume.bytes >= density.bytes + color.bytes


def test_what_cannot_be_read_says_why(vdb_file, tmp_path):
    assert issubclass(wn.VolumeFileError, RuntimeError)
    with pytest.raises(wn.VolumeFileError, match="does not exist"):
        wn.read_volume_grids(str(tmp_path / "missing.vdb"), ["density"])
    text = tmp_path / "text.vdb"
    text.write_text("not OpenVDB\n")
    with pytest.raises(wn.VolumeFileError, match="not a readable OpenVDB file"):
        wn.vdb_grids(str(text))
    with pytest.raises(wn.VolumeFileError, match="has no grid named 'flame'"):
        wn.read_volume_grids(vdb_file, ["flame"])
    with pytest.raises(wn.VolumeFileError, match="holds bool values"):
        wn.read_volume_grids(vdb_file, ["mask"])
    (density,) = wn.read_volume_grids(vdb_file, ["density"])
    with pytest.raises(ValueError, match="channel"):
        wn.VolumeObject(np.eye(4), color=density)
