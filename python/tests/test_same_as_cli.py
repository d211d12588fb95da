"""The module writes what the command line writes: the same garment, the
same .vdb but its UUID, the same .vol files, with the same options."""

import os

import pytest

import yarnvox
from volume_files import vdb_bytes_but_uuid


def test_generate_writes_the_command_lines_garment(scratch, cli):
    garment = yarnvox.generate("py.bcc", pattern="twill", shape="sphere", crossings=80, seed=5, yarn_radius=0.25)
    cli.run("gen", "--pattern", "twill", "--shape", "sphere", "--crossings", 80, "--seed", 5, "--yarn-radius", 0.25,
            "-o", "cli.bcc")
    assert open("py.bcc", "rb").read() == open("cli.bcc", "rb").read()
    assert garment["yarn_radius"] == 0.25
    assert garment["control_points"] == sum(len(y) for y in garment["yarns"]) > 0
    assert all(y.shape[1] == 3 for y in garment["yarns"])
    assert len(garment["closed"]) == len(garment["yarns"])


# Each case: the module's keyword arguments and the command line's words for them.
CASES = {
    "cpu-defaults": (dict(resolution=64, backend="cpu"), ["--resolution", "64", "--backend", "cpu"]),
    "gl-float-lod-disk": (
        dict(resolution=72, backend="gl", twist=-1.5, cross_section="disk", precision="float", lod=1),
        ["--resolution", "72", "--backend", "gl", "--twist", "-1.5", "--cross-section", "disk",
         "--precision", "float", "--lod", "1"],
    ),
    "cpu-voxel-size-radius": (
        dict(voxel_size=0.25, yarn_radius=0.2, slices_per_segment=8, reduce="max", backend="cpu"),
        ["--voxel-size", "0.25", "--yarn-radius", "0.2", "--slices-per-segment", "8", "--reduce", "max",
         "--backend", "cpu"],
    ),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_voxelize_writes_the_command_lines_vdb(case, knit, cli):
    kwargs, words = CASES[case]
    report = yarnvox.voxelize(knit, "py.vdb", **kwargs)
    cli.run("voxelize", knit, "-o", "cli.vdb", *words)
    assert vdb_bytes_but_uuid("py.vdb") == vdb_bytes_but_uuid("cli.vdb")
    assert report["output"] == "py.vdb" and report["active_voxels"] > 0
    assert yarnvox.read_metadata("py.vdb")["backend"] == kwargs["backend"]


def test_voxelize_writes_the_command_lines_vol_files(knit, cli):
    yarnvox.voxelize(knit, "py.vol", resolution=48, backend="cpu", quiet=True)
    cli.run("voxelize", knit, "-o", "cli.vol", "--resolution", 48, "--backend", "cpu", "--quiet")
    for suffix in (".vol", ".orientation.vol"):
        assert open("py" + suffix, "rb").read() == open("cli" + suffix, "rb").read(), suffix
    assert sorted(os.listdir(".")) == sorted([knit, "cli.vol", "cli.orientation.vol", "py.vol", "py.orientation.vol"])


def test_several_garments_into_a_folder(knit, cli):
    cli.run("gen", "--crossings", 40, "-o", "flat.bcc")
    reports = yarnvox.voxelize([knit, "flat.bcc"], "py", resolution=40, backend="cpu")
    cli.run("voxelize", knit, "flat.bcc", "-o", "cli", "--resolution", 40, "--backend", "cpu")
    assert [r["output"] for r in reports] == [os.path.join("py", "knit.vdb"), os.path.join("py", "flat.vdb")]
    for name in ("knit.vdb", "flat.vdb"):
        assert vdb_bytes_but_uuid(os.path.join("py", name)) == vdb_bytes_but_uuid(os.path.join("cli", name))


def test_the_run_records_its_yarn_radius(knit):
    yarnvox.voxelize(knit, "py.vdb", resolution=32, backend="cpu", twist=1.25)
    meta = yarnvox.read_metadata("py.vdb")
    assert (meta["yarn_radius"], meta["yarn_radius_source"]) == (0.3, "file")  # what `yarnvox gen` records
    assert (meta["input"], meta["twist"], meta["resolution"]) == (knit, 1.25, 32)
    # Touching yarns lie two radii apart: the estimate is of the generator's spacing, not 0.
    assert 0 < yarnvox.estimate_yarn_radius(knit)["radius"] < 1
