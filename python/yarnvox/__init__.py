"""yarnvox from Python: yarn-level garments (BCC) into volumes of fibre
density and orientation, with the command line's options, defaults, checks
and files (docs/python.md).

    import yarnvox
    yarnvox.generate("garment.bcc", pattern="knit", shape="cylinder", crossings=400)
    yarnvox.voxelize("garment.bcc", "garment.vdb", resolution=128, twist=2)
    volume = yarnvox.read_volume("garment.vdb")          # numpy arrays
    volume = yarnvox.voxelize_arrays("garment.bcc", resolution=64)   # no file kept

Options are the command line's long options as keyword arguments, dashes
written as underscores (--yarn-radius: yarn_radius=0.1); a flag (--albedo)
takes True or False. A value the command line would refuse raises
OptionError with the command line's message; a failed run raises Error with
its one line; nothing half-written is left either way.
"""

import os
import shutil
import tempfile

from . import _yarnvox
from ._yarnvox import Cancelled, Error, OptionError

__all__ = ["Error", "OptionError", "Cancelled", "generate", "read_bcc", "yarn_radius", "voxelize",
           "voxelize_arrays", "read_volume", "options"]


def options(command="voxelize"):
    """The keyword arguments `command` ("voxelize" or "gen") takes: {name: is_flag}."""
    return {name.replace("-", "_"): flag for name, flag in _yarnvox.option_names(command)}


def _word(value):
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    if isinstance(value, float):
        return repr(value)  # the shortest text that reads back as the same double
    if isinstance(value, (int, str)):
        return str(value)
    raise TypeError(f"{value!r}: give a number, a string or a path")


def _words(command, function, given, output, positional=()):
    """The command line's words for `command` with the keyword arguments
    `given`, `-o output` and the positional words (after "--", so that a
    name starting with '-' is still a garment)."""
    known = options(command)
    words = [command, f"--output={_word(output)}"]
    for key, value in given.items():
        if key not in known or key in ("output", "help"):
            raise TypeError(f"{function}() got an unexpected keyword argument '{key}'")
        if value is None:
            continue  # the command line's default
        if known[key]:
            if not isinstance(value, bool):
                raise TypeError(f"{function}(): {key} is a flag: give True or False, not {value!r}")
            if value:
                words.append("--" + key.replace("_", "-"))
        else:
            if isinstance(value, bool):
                raise TypeError(f"{function}(): {key} takes a value, not {value!r}")
            # --name=value: a value that starts with '-' (a negative twist) stays a value.
            words.append(f"--{key.replace('_', '-')}={_word(value)}")
    return words + (["--"] + [_word(p) for p in positional] if positional else [])


def _paths(garment):
    if isinstance(garment, (str, os.PathLike)):
        return [garment]
    return list(garment)


def generate(output, **options):
    """Writes a procedural garment to `output` (.bcc) as `yarnvox gen` does
    (pattern, shape, crossings, seed, spacing, yarn_radius) and returns it
    as read_bcc() does."""
    options.setdefault("quiet", True)  # what the command line prints, the returned garment says
    _yarnvox.run_command(_words("gen", "generate", options, output))
    return read_bcc(output)


def read_bcc(path):
    """A BCC garment as a dict: 'yarns' (one (n, 3) float64 array of control
    points each), 'closed', 'curve_type', 'yarn_radius' (0: none recorded),
    'control_points', 'segments'."""
    return _yarnvox.read_bcc(_word(path))


def yarn_radius(garment, yarn_radius=None, cross_section="fibers"):
    """The yarn radius `voxelize` would use for `garment` and where it comes
    from: {'radius', 'source' ('option', 'cross-section', 'file' or
    'estimated'), 'description'}."""
    return _yarnvox.yarn_radius(_word(garment), float(yarn_radius or 0.0), _word(cross_section))


def voxelize(garment, output, *, progress=None, **options):
    """Voxelizes `garment` (a .bcc path, or a list of them) into `output` as
    `yarnvox voxelize GARMENT -o OUTPUT --option value ...` does: the same
    options (resolution=N or voxel_size=H, twist, cross_section, albedo,
    precision, lod, backend, ...), defaults and files. Returns the run's
    report (a dict; a list of them for several garments).

    progress(stage, unit, done, total) is called as each stage advances (not
    with quiet=True); returning False, or raising, stops the run at the next
    region boundary, as Ctrl-C does, and raises Cancelled (or what it raised)
    with nothing half-written."""
    reports = _yarnvox.run_command(_words("voxelize", "voxelize", options, output, _paths(garment)), progress)
    return reports[0] if isinstance(garment, (str, os.PathLike)) and len(reports) == 1 else reports


def read_volume(path, *, dense=True, level=0, box=None):
    """The grids of a yarnvox .vdb as numpy arrays (for volumes that fit in
    memory), level `level` (0, or L of its density_lodL grids).

    dense=True: 'density' (nx, ny, nz) float32, 'orientation' and 'albedo'
    (nx, ny, nz, 3) or None, over `box` (i0, j0, k0, i1, j1, k1 voxel
    indices, the maximum exclusive) or the active voxels' bounding box;
    'origin' is the box's minimum index, empty voxels hold 0.
    dense=False: the density's 8^3 leaves as stored: 'origins' (n, 3) int32,
    'density' (n, 8, 8, 8), 'active' (n, 8, 8, 8) bool, 'orientation' and
    'albedo' (n, 8, 8, 8, 3) or None; leaf i's voxel [x, y, z] is index
    origins[i] + (x, y, z).
    Both: 'voxel_size' and 'index_to_world' (4 x 4: world = M @ (i, j, k, 1)).
    """
    if dense:
        return _yarnvox.read_dense(_word(path), int(level), None if box is None else tuple(int(v) for v in box))
    if box is not None:
        raise TypeError("read_volume(): box is for dense=True")
    return _yarnvox.read_sparse(_word(path), int(level))


def voxelize_arrays(garment, *, dense=True, level=0, box=None, progress=None, **options):
    """voxelize() into a temporary .vdb, read back as read_volume() returns
    it; no file is kept. For volumes that fit in memory."""
    if "lod" not in options and level == 0:
        options["lod"] = 0  # no pyramid to write when level 0 is all that is read
    scratch = tempfile.mkdtemp(prefix="yarnvox-")
    try:
        path = os.path.join(scratch, "volume.vdb")
        voxelize(garment, path, progress=progress, **options)
        return read_volume(path, dense=dense, level=level, box=box)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
