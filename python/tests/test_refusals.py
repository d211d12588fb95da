"""Bad arguments raise, with the command line's own line, and leave nothing
behind; a progress callback hears the run and can stop it cleanly."""

import os

import pytest

import yarnvox

# Keyword arguments the command line refuses, and its words for them.
REFUSED = {
    "not-whole": (dict(resolution=1.5), ["--resolution", "1.5"]),
    "too-small": (dict(resolution=4), ["--resolution", "4"]),
    "bad-word": (dict(resolution=64, reduce="median"), ["--resolution", "64", "--reduce", "median"]),
    "both-sizes": (dict(resolution=64, voxel_size=0.1), ["--resolution", "64", "--voxel-size", "0.1"]),
    "nan-length": (dict(voxel_size=float("nan")), ["--voxel-size", "nan"]),
    "bad-lod": (dict(resolution=64, lod="some"), ["--resolution", "64", "--lod", "some"]),
}


@pytest.mark.parametrize("case", sorted(REFUSED))
def test_a_refused_option_raises_the_command_lines_line(case, knit, cli):
    kwargs, words = REFUSED[case]
    with pytest.raises(yarnvox.OptionError) as raised:
        yarnvox.voxelize(knit, "out.vdb", **kwargs)
    assert str(raised.value) == cli.error_line("voxelize", knit, "-o", "out.vdb", *words)
    assert isinstance(raised.value, ValueError) and isinstance(raised.value, yarnvox.Error)
    assert sorted(os.listdir(".")) == [knit]


RUN_ERRORS = {
    "no-size": ([], {}),
    "albedo-without-colour": (["--resolution", "32", "--albedo"], dict(resolution=32, albedo=True)),
    "no-garment-file": (["--resolution", "32"], dict(resolution=32)),
}


@pytest.mark.parametrize("case", sorted(RUN_ERRORS))
def test_a_failed_run_raises_its_one_line(case, knit, cli):
    words, kwargs = RUN_ERRORS[case]
    garment = "missing.bcc" if case == "no-garment-file" else knit
    expected = cli.error_line("voxelize", garment, "-o", "out.vdb", *words)
    with pytest.raises(yarnvox.Error) as raised:
        yarnvox.voxelize(garment, "out.vdb", **kwargs)
    assert str(raised.value) == expected and "\n" not in expected
    assert not os.path.exists("out.vdb")


def test_a_damaged_garment_raises_and_writes_nothing(scratch, cli):
    with open("cut.bcc", "wb") as f:
        f.write(b"BCC\x44" + b"\x00" * 20)
    expected = cli.error_line("voxelize", "cut.bcc", "-o", "out.vdb", "--resolution", "32")
    with pytest.raises(yarnvox.Error, match="cut.bcc") as raised:
        yarnvox.voxelize("cut.bcc", "out.vdb", resolution=32)
    assert str(raised.value) == expected
    with pytest.raises(yarnvox.Error):
        yarnvox.read_bcc("cut.bcc")
    assert sorted(os.listdir(".")) == ["cut.bcc"]


def test_python_mistakes_are_type_errors(knit):
    with pytest.raises(TypeError, match="unexpected keyword argument 'resolutoin'"):
        yarnvox.voxelize(knit, "out.vdb", resolutoin=64)
    with pytest.raises(TypeError, match="albedo is a flag"):
        yarnvox.voxelize(knit, "out.vdb", resolution=64, albedo="yes")
    with pytest.raises(TypeError, match="resolution takes a value"):
        yarnvox.voxelize(knit, "out.vdb", resolution=True)
    assert not os.path.exists("out.vdb")


def test_the_options_are_the_command_lines(knit):
    names = yarnvox.options("voxelize")
    for name in ("resolution", "voxel_size", "yarn_radius", "twist", "cross_section", "precision", "lod"):
        assert names[name] is False
    for name in ("albedo", "quiet", "resume"):
        assert names[name] is True


def test_progress_is_heard_until_every_region_is_done(knit):
    heard = []
    yarnvox.voxelize(knit, "out.vdb", resolution=64, backend="cpu", fragment_budget=5000,
                     progress=lambda *args: heard.append(args))
    regions = [h for h in heard if h[:2] == ("voxelize", "regions")]
    assert len(regions) >= 2, heard
    assert regions[0][2] == 0 and regions[-1][2] == regions[-1][3] > 1
    assert all(done <= total for _, _, done, total in heard)


def test_a_callback_that_answers_false_cancels_and_writes_nothing(knit):
    # The callback answers the first progress line; the SIGINT it sends has
    # to land while the regions are still being voxelized. At resolution 64
    # they took 20 ms, which a loaded machine's scheduler could miss (the run
    # then finished); at 192, 250 regions of about 0.3 s.
    with pytest.raises(yarnvox.Cancelled, match="interrupted by SIGINT .*nothing was written"):
        yarnvox.voxelize(knit, "out.vdb", resolution=192, backend="cpu", fragment_budget=5000,
                         progress=lambda *args: False)
    assert sorted(os.listdir(".")) == [knit]


def test_a_callback_that_raises_stops_the_run_with_its_exception(knit):
    class Enough(Exception):
        pass

    def progress(stage, unit, done, total):
        if done >= 1:
            raise Enough()

    # As above: the run must still be in its regions when the exception's
    # SIGINT lands (at 64 a loaded machine could finish it first).
    with pytest.raises(Enough):
        yarnvox.voxelize(knit, "out.vdb", resolution=192, backend="cpu", fragment_budget=5000, progress=progress)
    assert sorted(os.listdir(".")) == [knit]
    # Nothing of the stopped run is left to the next one: it runs to the end.
    assert yarnvox.voxelize(knit, "out.vdb", resolution=32, backend="cpu")["active_voxels"] > 0
