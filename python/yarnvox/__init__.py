"""yarnvox from Python: yarn-level garments (BCC) into volumes of fibre
density and orientation, with the command line's options, defaults, checks
and files (docs/python.md).

    import yarnvox
    yarnvox.generate("garment.bcc", pattern="knit", shape="cylinder", crossings=400)
    yarnvox.voxelize("garment.bcc", "garment.vdb", resolution=128, twist=2)
    volume = yarnvox.read_volume("garment.vdb")                      # numpy arrays
    volume = yarnvox.voxelize_arrays("garment.bcc", resolution=64)   # no file kept

generate() and voxelize() run the yarnvox command line (the one built or
installed with this package; YARNVOX_EXECUTABLE names another), so the
options, their defaults and checks, the messages and the files are its own.
Options are its long options as keyword arguments, dashes written as
underscores (--yarn-radius: yarn_radius=0.1); a flag (--albedo) takes True
or False. A value the command line refuses raises OptionError with its
message; a failed run raises Error with its one line; nothing half-written
is left either way.
"""

import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile

from . import _yarnvox
from ._yarnvox import Error

__all__ = ["Error", "OptionError", "Cancelled", "generate", "read_bcc", "estimate_yarn_radius", "voxelize",
           "voxelize_arrays", "read_volume", "read_metadata", "options", "executable"]


class OptionError(Error, ValueError):
    """An option the command line refuses (its message, as after "yarnvox: error: ")."""


class Cancelled(Error):
    """The progress callback stopped the run (it answered False)."""


def executable():
    """The yarnvox command line this package runs: $YARNVOX_EXECUTABLE, else
    the one of its build tree or install prefix, else the PATH's."""
    named = os.environ.get("YARNVOX_EXECUTABLE")
    if named:
        return named
    here = os.path.dirname(os.path.abspath(__file__))
    for candidate in (os.path.join(here, "..", "..", "yarnvox"),  # build/python/yarnvox -> build/yarnvox
                      os.path.join(here, "..", "..", "..", "..", "bin", "yarnvox")):  # PREFIX/lib/python3.N/dist-packages
        if os.path.isfile(candidate) and os.access(candidate, os.X_OK):
            return os.path.normpath(candidate)
    found = shutil.which("yarnvox")
    if not found:
        raise Error("no yarnvox command line: build or install yarnvox (tools/install), or set YARNVOX_EXECUTABLE")
    return found


# "  --twist FLOAT:NUMBER=0   ...", "  -o,--output TEXT REQUIRED ...", "  --albedo   ...":
# CLI11 writes an option's type (upper case) one space after its name, a flag's description further on.
_OPTION_LINE = re.compile(r"^\s+(?:-\w,)?--([a-z][a-z0-9-]*)( [A-Z]+\b)?")


def options(command="voxelize"):
    """The keyword arguments `command` ("voxelize" or "gen") takes, read from
    the command line's --help: {name: is_flag}."""
    help_text = subprocess.run([executable(), command, "--help"], capture_output=True, text=True, check=True).stdout
    found = {}
    for line in help_text.splitlines():
        m = _OPTION_LINE.match(line)
        if m and m.group(1) != "help":
            found[m.group(1).replace("-", "_")] = m.group(2) is None
    return found


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


_PROGRESS = re.compile(r"^progress: (\S+) (\d+)/(\d+) ?(.*)$")
_SUMMARY = re.compile(r"^(.*): (\d+) slices -> (\d+) active voxels in (\d+) bricks \(grid (\d+)x(\d+)x(\d+), "
                      r"voxel ([^)]+)\), ([\d.]+) s voxelize$")


def _run(words, progress=None):
    """Runs `yarnvox WORDS`; the summary lines it prints on stdout, parsed
    into one report a garment. progress lines go to `progress`, other
    stderr lines to sys.stderr."""
    # A session of its own: Ctrl-C on the terminal reaches this process only,
    # which passes one SIGINT on (a second would end yarnvox at once).
    process = subprocess.Popen([executable(), *words], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               start_new_session=True)
    stopped, raised, last = False, None, ""
    try:
        for line in process.stderr:
            line = line.rstrip("\n")
            m = _PROGRESS.match(line)
            if not m:
                if line.strip():
                    last = line
                    sys.stderr.write(line + "\n")
                continue
            if progress is None or stopped:
                continue
            done, total = int(m.group(2)), int(m.group(3))
            try:
                stopped = progress(m.group(1), m.group(4), done, total) is False
            except BaseException as e:  # the callback's own exception, raised once the run has stopped
                raised, stopped = e, True
            # As Ctrl-C: yarnvox stops at the next region boundary and writes
            # nothing. Once a stage is done there is nothing left to stop (the
            # signal could only end yarnvox while it writes): the run finishes.
            if stopped and done < total:
                process.send_signal(signal.SIGINT)
        out = process.stdout.read()
        code = process.wait()
    except BaseException:  # KeyboardInterrupt while waiting: the run stops as after Ctrl-C, then it goes on up
        process.send_signal(signal.SIGINT)
        process.wait()
        raise
    finally:
        process.stdout.close()
        process.stderr.close()
    if raised is not None:
        raise raised
    if code != 0:
        message = last[len("yarnvox: error: "):] if last.startswith("yarnvox: error: ") else last
        if stopped:
            raise Cancelled(message)
        if message.endswith(" (see --help)"):
            raise OptionError(message[: -len(" (see --help)")])
        raise Error(message or f"yarnvox {words[0]} ended with status {code}")
    reports, lines = [], out.splitlines()
    for i, line in enumerate(lines):
        m = _SUMMARY.match(line)
        if m:
            wrote = lines[i + 1][len("wrote "):] if i + 1 < len(lines) and lines[i + 1].startswith("wrote ") else None
            reports.append({"input": m.group(1), "output": wrote, "slices": int(m.group(2)),
                            "active_voxels": int(m.group(3)), "bricks": int(m.group(4)),
                            "dims": (int(m.group(5)), int(m.group(6)), int(m.group(7))),
                            "voxel_size": float(m.group(8)), "voxelize_seconds": float(m.group(9))})
    return reports


def generate(output, **options):
    """Writes a procedural garment to `output` (.bcc) as `yarnvox gen` does
    (pattern, shape, crossings, seed, spacing, yarn_radius) and returns it
    as read_bcc() does."""
    options.setdefault("quiet", True)  # what the command line prints, the returned garment says
    _run(_words("gen", "generate", options, output))
    return read_bcc(output)


def read_bcc(path):
    """A BCC garment as a dict: 'yarns' (one (n, 3) float64 array of control
    points each), 'closed', 'curve_type', 'yarn_radius' (0: none recorded),
    'control_points', 'segments'."""
    return _yarnvox.read_bcc(_word(path))


def estimate_yarn_radius(garment):
    """The yarn radius voxelize estimates for a garment that records none (and
    no --yarn-radius or cross-section PNG gives one): {'radius' (0: no yarns
    touch), 'samples', 'contacts'}."""
    return _yarnvox.estimate_yarn_radius(_word(garment))


def voxelize(garment, output, *, progress=None, **options):
    """Voxelizes `garment` (a .bcc path, or a list of them) into `output` as
    `yarnvox voxelize GARMENT -o OUTPUT --option value ...` does: the same
    options (resolution=N or voxel_size=H, twist, cross_section, albedo,
    precision, lod, backend, ...), defaults and files. Returns the run's
    report (a dict; a list of them for several garments).

    The report holds what the command line's summary says: input, output,
    slices, active_voxels, bricks, dims, voxel_size, voxelize_seconds (none
    with quiet=True, which prints no summary).

    progress(stage, unit, done, total) is called as each stage advances (not
    with quiet=True); returning False, or raising, stops the run at the next
    region boundary, as Ctrl-C does, and raises Cancelled (or what it raised)
    with nothing half-written."""
    words = _words("voxelize", "voxelize", options, output, _paths(garment))
    if progress is not None:
        words.insert(1, "--progress-lines")
    reports = _run(words, progress)
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


def read_metadata(path):
    """What a yarnvox .vdb records about its run (input, backend,
    cross_section, resolution, yarn_radius, yarn_radius_source, twist,
    lod_levels, ...), as a dict."""
    return _yarnvox.read_metadata(_word(path))


def voxelize_arrays(garment, *, dense=True, level=0, box=None, progress=None, **options):
    """voxelize() into a temporary .vdb, read back as read_volume() returns
    it; no file is kept. For volumes that fit in memory. The values are
    float unless precision="half" is given (the file's default, half, saves
    bytes on disk, and no file is kept here)."""
    if "lod" not in options and level == 0:
        options["lod"] = 0  # no pyramid to write when level 0 is all that is read
    options.setdefault("precision", "float")
    scratch = tempfile.mkdtemp(prefix="yarnvox-")
    try:
        path = os.path.join(scratch, "volume.vdb")
        voxelize(garment, path, progress=progress, **options)
        return read_volume(path, dense=dense, level=level, box=box)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
