"""The module's arrays hold the file's values: the dense box equals a
float32 .vol that `yarnvox export` writes of the same box (through OpenVDB,
read back by the tests' own reader), the leaves equal the box, and a coarse
level keeps the fibre volume (a coarse voxel is the mean of the 8 below it)."""

import numpy as np
import pytest

import yarnvox
from volume_files import read_vol


@pytest.fixture
def volume(knit, cli):
    cli.run("voxelize", knit, "-o", "cli.vdb", "--resolution", 64, "--backend", "cpu", "--twist", 2, "--lod", 1)
    return "cli.vdb"


def test_dense_arrays_equal_the_exported_vol(volume, cli):
    dense = yarnvox.read_volume(volume)
    nx, ny, nz = dense["density"].shape
    i0, j0, k0 = dense["origin"]
    cli.run("export", volume, "-o", "box.vol", "--bbox", f"{i0},{j0},{k0},{i0 + nx},{j0 + ny},{k0 + nz}")
    np.testing.assert_array_equal(dense["density"], read_vol("box.vol"))
    np.testing.assert_array_equal(dense["orientation"], read_vol("box.orientation.vol"))
    assert dense["albedo"] is None
    assert dense["density"].max() > 0.5 and dense["density"].min() == 0.0
    # The index-to-world matrix: a scale by the voxel size (and a translation).
    m = dense["index_to_world"]
    np.testing.assert_allclose(np.diag(m)[:3], dense["voxel_size"])
    assert m[3].tolist() == [0, 0, 0, 1]


def test_a_box_crops_the_same_values(volume):
    whole = yarnvox.read_volume(volume)
    i0, j0, k0 = whole["origin"]
    part = yarnvox.read_volume(volume, box=(i0 + 3, j0 + 2, k0 + 1, i0 + 20, j0 + 9, k0 + 30))
    np.testing.assert_array_equal(part["density"], whole["density"][3:20, 2:9, 1:30])
    assert part["origin"] == (i0 + 3, j0 + 2, k0 + 1)
    with pytest.raises(yarnvox.Error, match="box holds no voxel"):
        yarnvox.read_volume(volume, box=(0, 0, 0, 0, 4, 4))


def test_leaves_equal_the_dense_box(volume):
    dense = yarnvox.read_volume(volume)
    leaves = yarnvox.read_volume(volume, dense=False)
    n = len(leaves["origins"])
    assert n > 0 and leaves["density"].shape == (n, 8, 8, 8) and leaves["orientation"].shape == (n, 8, 8, 8, 3)
    assert np.all(leaves["origins"] % 8 == 0)
    origin = np.array(dense["origin"])
    found = 0
    for i in range(n):
        idx = np.argwhere(leaves["active"][i])
        voxel = idx + leaves["origins"][i] - origin
        d = dense["density"][voxel[:, 0], voxel[:, 1], voxel[:, 2]]
        np.testing.assert_array_equal(leaves["density"][i][tuple(idx.T)], d)
        np.testing.assert_array_equal(leaves["orientation"][i][tuple(idx.T)],
                                      dense["orientation"][voxel[:, 0], voxel[:, 1], voxel[:, 2]])
        found += len(idx)
    assert found == np.count_nonzero(dense["density"])  # every active voxel holds fibre


def test_a_coarse_level_keeps_the_fibre_volume(volume):
    fine = yarnvox.read_volume(volume, dense=False)
    coarse = yarnvox.read_volume(volume, dense=False, level=1)
    assert coarse["voxel_size"] == pytest.approx(2 * fine["voxel_size"])
    assert 8 * coarse["density"].sum(dtype=np.float64) == pytest.approx(fine["density"].sum(dtype=np.float64), rel=1e-5)
    with pytest.raises(yarnvox.Error, match="no float grid density_lod2"):
        yarnvox.read_volume(volume, level=2)


def test_voxelize_arrays_equal_the_written_file(knit, volume, cli):
    # The file's default precision is half; the arrays' float, unless asked for half.
    halves = yarnvox.voxelize_arrays(knit, resolution=64, backend="cpu", twist=2, precision="half")
    from_file = yarnvox.read_volume(volume)
    np.testing.assert_array_equal(halves["density"], from_file["density"])
    np.testing.assert_array_equal(halves["orientation"], from_file["orientation"])
    assert halves["origin"] == from_file["origin"]
    floats = yarnvox.voxelize_arrays(knit, resolution=64, backend="cpu", twist=2)
    cli.run("voxelize", knit, "-o", "float.vdb", "--resolution", 64, "--backend", "cpu", "--twist", 2,
            "--precision", "float")
    from_float_file = yarnvox.read_volume("float.vdb")
    np.testing.assert_array_equal(floats["density"], from_float_file["density"])
    np.testing.assert_array_equal(floats["orientation"], from_float_file["orientation"])
    # The halves are the floats rounded (numpy's float16 rounds as OpenVDB's half does: to nearest, ties to even).
    np.testing.assert_array_equal(floats["density"].astype(np.float16).astype(np.float32), halves["density"])
    assert np.count_nonzero(floats["density"] != halves["density"]) > 0
