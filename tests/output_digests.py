#!/usr/bin/env python3
"""Digests of everything a set of small yarnvox runs writes, to show that a
change of the code leaves every output byte the same.

    tests/output_digests.py --yarnvox BIN --scratch DIR [--mpiexec MPIRUN]
                            [--compare GOLDEN] [--keep]

It makes small garments with `yarnvox gen` and a colour cross-section PNG,
runs the commands listed in CASES below in DIR (which it empties first), and
prints one line per output file: a stable name, the byte count and the
SHA-256 of the file's normalised content. All paths given to yarnvox are
relative to DIR (the .vdb, the manifest and --stats record the input path),
so the lines do not depend on where DIR is.

What is normalised (everything else is digested as written):
- .vdb: the 36 bytes of the UUID in the file header (bytes 21..56, after the
  magic, three version numbers and the offsets flag; formats/vdb-subset.md),
  which OpenVDB's format makes new for each file. The script checks that
  these bytes are a UUID before masking them.
- region files (`region-ID.yvb`): the run fingerprint (header bytes 16..23)
  and the header checksum that covers it (bytes 152..159;
  formats/brick-store.md). The fingerprint hashes the sampling code, shader
  texts included, so an edit to a shader's text that compiles to the same
  program changes it; every other byte (the region's identity, grid, bricks
  and their checksums) is compared. The script checks the file's magic first.
- work dir `manifest`: left out. Its format changed (a line grammar at
  8d8d9c1, JSON since) and it records the fingerprint; tests/test_brick_store
  checks what it holds, and every region file beside it is compared.
- --stats JSON: a whole number written as a double ("0.0", as nlohmann's
  writer has it since 8d8d9c1's "0") as the integer; and the values (not the
  keys, whose order and formatting are kept) of the keys in STATS_VARYING below: times, rates over times, the
  process's memory, the machine's thread count and GL driver, how the GL
  backend found its sample items; under mpirun
  also rank 0's own counts (STATS_VARYING_MPI), and with --method dense the
  sums over its racy values (STATS_VARYING_DENSE); and the process id in the
  name of the temporary .vdb that `voxelize -o X.vol|X.nvdb` gives as its
  `output` (X.partial-PID.vdb).
- .vol and .nvdb files, .bcc: nothing (none holds a time, a UUID, a path or
  a process id: checked by running the same binary several times, see
  docs/same-bytes.md).
- Left out: the .vdb of --method dense (its values differ from run to run:
  see its case below).

Cases marked "gl" need an OpenGL 4.5 context (Mesa's llvmpipe where there is
no GPU): where none can be made they fail, unless YV_GL_TESTS=skip is set,
when they are left out and the comparison ignores their golden lines (said
so). Cases marked "mpi" run `MPIRUN -np 2 yarnvox` (a yarnvox built with
-DYARNVOX_MPI=ON); without --mpiexec they are left out and ignored (said so).

--compare GOLDEN compares the lines with GOLDEN and exits 1 with a unified
diff when any differs (0 when all agree).

The golden file, tests/golden/output-digests-638f66a.txt, was made with the
yarnvox of commit 638f66a (built Release, -DYARNVOX_MPI=ON), with GL and MPI,
in a scratch directory on ext4 (the .vdb files' streamed layout needs a file
system that cuts ranges out of files: docs/same-bytes.md):

    tests/output_digests.py --yarnvox build/yarnvox \
        --scratch /tmp/yv-digests --mpiexec "$(command -v mpirun)" \
        > tests/golden/output-digests-638f66a.txt

How its lines differ from those of the earlier golden files (8d8d9c1,
8061731, ec8a3f0, 6d7a37d), and why: docs/same-bytes.md.

Regenerate it the same way (with the new binary, and a new file name saying
its commit, named in tests/CMakeLists.txt) only when a change of the output
is intended, and say in the commit which outputs changed and why.
"""

import argparse
import difflib
import hashlib
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import time
import zlib

# --stats keys whose values vary between two runs of the same binary on the
# same input, or between machines: the value is masked ("<varies>"), the key
# kept. A key matches at any depth; a key whose value is an object masks
# every value in it (its keys kept: `seconds` keeps the stage names).
STATS_VARYING = {
    # times (the suffix rule below catches these too; listed as found in 8d8d9c1's stats)
    "seconds",  # per stage: read, slices, plan, voxelize, merge, write, finish
    "vdb_seconds",  # read_regions, encode_leaves, topology, write
    "gl_context_seconds", "gl_program_seconds", "gpu_clear_seconds", "gpu_raster_seconds", "gpu_place_seconds",
    "gpu_sample_seconds", "gpu_brick_seconds", "gpu_resolve_seconds", "readback_seconds", "zoom_plan_seconds",
    "store_resolve_seconds", "store_encode_seconds", "store_write_seconds", "store_wait_seconds",
    # rates over times
    "slices_per_second", "active_voxels_per_second",
    # the process's memory, and the writer queue's peak (when the writer
    # thread catches up depends on the scheduling of threads)
    "peak_host_bytes", "store_peak_queued_bytes",
    # how much of the .vdb's leaves were written before the last region came
    # (the stream's thread against the regions' writers); how much was
    # streamed in all (vdb_streamed_bytes) does not vary
    "vdb_streamed_before_end_bytes",
    # the machine: its core count, and the GL driver's name and EGL platform
    # (llvmpipe names its LLVM version and vector width)
    "threads", "renderer", "platform",
    # how the GL backend found its sample items: chosen by the device and by
    # --sample-items (a raster's triangles or point sprites, or a compute
    # pass), and the primitives that drew them; the items, fragments and
    # every output byte are the same whichever it was
    "slice_primitive", "primitives_drawn",
}
# Any key ending in these is a time too.
STATS_VARYING_SUFFIXES = ("_seconds", "_per_second", "_ms")
# Under mpirun, rank 0 writes --stats with the counts of its own share of the
# work, and which regions each rank takes is decided at run time (the first
# rank free takes the next one): these vary from run to run. The summed
# counts (regions_computed, regions_resumed, ...) and the output's do not.
STATS_VARYING_MPI = {
    "samples", "fragments", "raster_passes", "overflow_retries", "fragment_list_growths",
    "bricks_summed_on_host", "gpu_peak_bytes", "sample_items", "slices_drawn", "primitives_drawn",
    "readback_bytes",
}
# --method dense: its fragments read, compare and write voxels without
# atomics (shaders/dense.frag: the paper's race, kept on purpose), so the
# values it writes vary from run to run on llvmpipe; its active voxels and
# the rest of its stats do not.
STATS_VARYING_DENSE = {"fiber_volume", "voxels_over_one", "mass_share_over_one"}


# ---------------------------------------------------------------- normalising

UUID_AT, UUID_LEN = 21, 36
UUID_RE = re.compile(rb"[0-9a-f]{8}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{12}")


def normalise_vdb(data, name):
    if len(data) < UUID_AT + UUID_LEN or struct.unpack_from("<q", data, 0)[0] != 0x56444220:
        raise SystemExit(f"{name}: not an OpenVDB file")
    if data[20] != 1 or not UUID_RE.fullmatch(data[UUID_AT:UUID_AT + UUID_LEN]):
        raise SystemExit(f"{name}: no UUID at bytes {UUID_AT}..{UUID_AT + UUID_LEN - 1}")
    return data[:UUID_AT] + b"0" * UUID_LEN + data[UUID_AT + UUID_LEN:]


class JsonSpans:
    """Finds the text span of every value of a JSON text, with its key path,
    so values can be masked while the text around them stays as written."""

    def __init__(self, text):
        self.t, self.i, self.spans = text, 0, []

    def ws(self):
        while self.i < len(self.t) and self.t[self.i] in " \t\r\n":
            self.i += 1

    def string(self):
        j = self.i + 1
        while self.t[j] != '"':
            j += 2 if self.t[j] == "\\" else 1
        s, self.i = self.t[self.i + 1:j], j + 1
        return s

    def value(self, path):
        self.ws()
        start, c = self.i, self.t[self.i]
        if c == "{":
            self.i += 1
            self.ws()
            while self.t[self.i] != "}":
                key = self.string()
                self.ws()
                assert self.t[self.i] == ":"
                self.i += 1
                self.value(path + [key])
                self.ws()
                if self.t[self.i] == ",":
                    self.i += 1
                    self.ws()
            self.i += 1
        elif c == "[":
            self.i += 1
            self.ws()
            while self.t[self.i] != "]":
                self.value(path + ["[]"])
                self.ws()
                if self.t[self.i] == ",":
                    self.i += 1
            self.i += 1
        elif c == '"':
            self.string()
        else:
            m = re.compile(r"[-+0-9.eE]+|true|false|null").match(self.t, self.i)
            assert m, f"bad JSON at {self.i}"
            self.i = m.end()
        self.spans.append((start, self.i, path))


def varying(path, more):
    """A value under a varying key (a nested object's every value)."""
    return any(k in STATS_VARYING or k in more or k.endswith(STATS_VARYING_SUFFIXES) for k in path)


def normalise_stats(data, name, more=frozenset()):
    text = data.decode()
    # `voxelize -o X.vol|X.nvdb` names its temporary .vdb (X.partial-PID.vdb)
    # as its output: the process id is masked, the rest kept.
    text = re.sub(r'("output": "[^"]*\.partial-)[0-9]+(\.vdb")', r"\1<pid>\2", text)
    scan = JsonSpans(text)
    scan.value([])
    # Scalars only: the keys of a nested object (a stage's name) are kept.
    masked = [(start, end) for start, end, path in scan.spans if varying(path, more) and text[start] not in "{["]
    for start, end in sorted(masked, reverse=True):
        text = text[:start] + '"<varies>"' + text[end:]
    # A whole number written as a double: "0" at 8d8d9c1, "0.0" through
    # nlohmann's writer since; the same value, written one way here.
    text = re.sub(r'(?<=[:\[,\s])(-?[0-9]+)\.0(?=[,\s}\]])', r"\1", text)
    return text.encode()


REGION_MAGIC = b"YVBRICKS"
FINGERPRINT_AT, HEADER_CHECKSUM_AT = 16, 152


def normalise_region(data, name):
    if len(data) < HEADER_CHECKSUM_AT + 8 or not data.startswith(REGION_MAGIC):
        raise SystemExit(f"{name}: not a region file")
    data = data[:FINGERPRINT_AT] + b"\0" * 8 + data[FINGERPRINT_AT + 8:]
    return data[:HEADER_CHECKSUM_AT] + b"\0" * 8 + data[HEADER_CHECKSUM_AT + 8:]


def normalise(path, name, stats_varying=frozenset()):
    data = open(path, "rb").read()
    base = os.path.basename(path)
    if base.endswith(".vdb"):
        data = normalise_vdb(data, name)
    elif base.startswith("region-") and base.endswith(".yvb"):
        data = normalise_region(data, name)
    elif base.endswith(".json"):
        data = normalise_stats(data, name, stats_varying)
    return data


# ---------------------------------------------------------------- inputs

def write_png(path, size):
    """An RGBA PNG, a disc of fibre (alpha 255) whose left half is rust red and
    right half slate blue, transparent around it: a colour cross-section."""
    rows = b""
    c = (size - 1) / 2
    for y in range(size):
        rows += b"\0"
        for x in range(size):
            inside = (x - c) ** 2 + (y - c) ** 2 <= (size / 2) ** 2
            rgb = (183, 65, 14) if x < size // 2 else (70, 90, 160)
            rows += bytes(rgb) + bytes([255 if inside else 0])

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))

    png = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", size, size, 8, 6, 0, 0, 0)) +
           chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b""))
    with open(path, "wb") as f:
        f.write(png)


# ---------------------------------------------------------------- the runs

GARMENTS = {
    "knit-cylinder.bcc": "gen --pattern knit --shape cylinder --crossings 300 --seed 3",
    "twill-flat.bcc": "gen --pattern twill --shape flat --crossings 256 --seed 5",
    "plain-cylinder.bcc": "gen --pattern plain --shape cylinder --crossings 200 --seed 7",
}

# Small enough for llvmpipe on 2 cores, also under AddressSanitizer; the
# fragment budget splits the runs into several zoom regions.
COMMON = "--twist 2 --fragment-budget 60000 --quiet"
R = "--resolution 128"
# No level-of-detail grids: what a .vdb held without --lod before the preview
# pyramid became voxelize's and merge's default. The golden lines name
# outputs, not commands: the runs that wrote a .vdb without --lod ask for
# none, so their files are the bytes of 8d8d9c1 still (the preview has tests
# of its own, tests/test_lod_preview.cpp).
NO_LOD = "--lod 0"

# (name, needs, commands, outputs[, written]): commands run in order in
# DIR/name (each a yarnvox command line, "mpi: ..." for mpirun -np 2 yarnvox
# ..., or a python callable taking the case folder); outputs are the files or
# folders (every file in them) under DIR/name that are digested; written, the
# files it writes that are not (each with its reason). Anything else in
# DIR/name fails the script. needs: a set of "gl", "mpi".


def partial(work):
    """Makes a completed work dir look like a run killed part-way: every
    other region file gone, one damaged, the manifest without `complete` and
    the stage times (as a killed run leaves it)."""
    def apply(case_dir):
        d = os.path.join(case_dir, work)
        regions = sorted((f for f in os.listdir(d) if f.endswith(".yvb")), key=lambda f: int(f[7:-4]))
        assert len(regions) >= 4, f"{d}: only {len(regions)} regions"
        for f in regions[::2]:
            os.remove(os.path.join(d, f))
        victim = os.path.join(d, regions[1])
        with open(victim, "r+b") as f:
            f.seek(-10, os.SEEK_END)
            b = f.read(1)
            f.seek(-10, os.SEEK_END)
            f.write(bytes([b[0] ^ 0x5A]))
        m = os.path.join(d, "manifest")
        text = open(m, "rb").read()
        if text.startswith(b"{"):  # JSON (formats/brick-store.md): a killed run has no completion yet
            manifest = json.loads(text)
            manifest.pop("complete_regions", None)
            manifest.pop("stage_seconds", None)
            text = json.dumps(manifest, indent=2).encode() + b"\n"
        else:  # the line grammar of 8d8d9c1: everything before `complete`
            lines = text.split(b"\n")
            cut = next(i for i, l in enumerate(lines) if l.startswith(b"complete "))
            text = b"\n".join(lines[:cut]) + b"\n"
        with open(m, "wb") as f:
            f.write(text)
    return apply


def write_text(name, text):
    def apply(case_dir):
        with open(os.path.join(case_dir, name), "w") as f:
            f.write(text)
    return apply


def copy_dir(src, dst):
    def apply(case_dir):
        shutil.copytree(os.path.join(case_dir, src), os.path.join(case_dir, dst))
    return apply


G = "../"  # garments and the PNG lie in DIR, cases in DIR/NAME

CASES = []
for be in ("cpu", "gl"):
    needs = {"gl"} if be == "gl" else set()
    B = f"--backend {be} {R} {COMMON}"
    B64 = f"--backend {be} --resolution 64 {COMMON}"
    CASES += [
        # In memory (the default), fibres cross-section, with --stats.
        (f"{be}-memory", needs,
         [f"voxelize {G}knit-cylinder.bcc -o out.vdb {B} {NO_LOD} --stats stats.json"],
         ["out.vdb", "stats.json"]),
        # --work-dir DIR: region files and manifest; then merge, with options
        # of its own; then --resume after the completed run.
        (f"{be}-workdir", needs,
         [f"voxelize {G}twill-flat.bcc -o out.vdb {B} {NO_LOD} --work-dir work --stats stats.json",
          f"merge work -o merged.vdb {NO_LOD} --quiet",
          "merge work -o merged-lod1-half-zip.vdb --lod 1 --precision half --vdb-compression zip --quiet",
          copy_dir("work", "work-resumed"),
          f"voxelize {G}twill-flat.bcc -o resumed.vdb {B} {NO_LOD} --work-dir work-resumed --resume "
          "--stats resumed.json"],
         ["out.vdb", "stats.json", "work", "merged.vdb", "merged-lod1-half-zip.vdb", "work-resumed",
          "resumed.vdb", "resumed.json"]),
        # The default work dir kept (--keep-work-dir); then --resume after a
        # partial run (regions missing, one damaged, no `complete`).
        (f"{be}-keep-resume", needs,
         [f"voxelize {G}plain-cylinder.bcc -o out.vdb {B} {NO_LOD} --keep-work-dir --cross-section disk",
          copy_dir("out.vdb.work", "work-partial"),
          partial("work-partial"),
          f"voxelize {G}plain-cylinder.bcc -o resumed.vdb {B} {NO_LOD} --cross-section disk "
          "--work-dir work-partial --resume --stats resumed.json"],
         ["out.vdb", "out.vdb.work", "resumed.vdb", "work-partial", "resumed.json"]),
        # Level-of-detail grids, half precision, blosc.
        (f"{be}-lod2-half", needs,
         [f"voxelize {G}knit-cylinder.bcc -o out.vdb {B} --lod 2 --precision half --vdb-compression blosc "
          "--stats stats.json"],
         ["out.vdb", "stats.json"]),
        # The paper's max reduce, summed overlap, supersampling (at 64: it
        # makes 4 times the samples), no compression.
        (f"{be}-max", needs,
         [f"voxelize {G}twill-flat.bcc -o out.vdb {B64} {NO_LOD} --reduce max --overlap sum --supersample 2 "
          "--vdb-compression none --stats stats.json"],
         ["out.vdb", "stats.json"]),
        # Colour: --albedo from the PNG, with --lod 1, in a work dir; export
        # of its .vol (3 grids) and .nvdb.
        (f"{be}-albedo", needs,
         [f"voxelize {G}knit-cylinder.bcc -o out.vdb {B} --cross-section {G}colour.png --albedo --lod 1 "
          "--work-dir work --stats stats.json",
          "export out.vdb -o out.vol --quiet",
          "export out.vdb -o out.nvdb --quiet",
          "merge work -o merged.vdb --lod 1 --quiet"],
         ["out.vdb", "stats.json", "work", "out.vol", "out.albedo.vol", "out.orientation.vol", "out.nvdb",
          "merged.vdb"]),
        # Straight to .vol and .nvdb (--format from the extension).
        (f"{be}-vol-nvdb", needs,
         [f"voxelize {G}plain-cylinder.bcc -o out.vol {B} --stats vol.json",
          f"voxelize {G}plain-cylinder.bcc -o out.nvdb {B} --stats nvdb.json"],
         ["out.vol", "out.orientation.vol", "vol.json", "out.nvdb", "nvdb.json"]),
        # Options given another way: --voxel-size, --slice-spacing,
        # --yarn-radius; several garments into a folder (and --stats into
        # one); --list, --slices-per-segment, and the defaults written out;
        # export --bbox-world with --format.
        (f"{be}-options", needs,
         [f"voxelize {G}knit-cylinder.bcc {G}plain-cylinder.bcc -o multi --backend {be} --voxel-size 0.25 "
          f"--slice-spacing 0.1 --yarn-radius 0.35 --twist 1 --fragment-budget 60000 {NO_LOD} --quiet "
          "--stats multi-stats",
          write_text("garments.txt", f"{G}twill-flat.bcc\n{G}plain-cylinder.bcc\n"),
          f"voxelize --list garments.txt -o listed --backend {be} --resolution 64 --slices-per-segment 3 "
          f"--cross-section fibers --reduce mean --overlap clamp --precision float --vdb-compression mask {NO_LOD} "
          "--quiet",
          "export multi/knit-cylinder.vdb -o world.vol --format vol --bbox-world -2,-2,-1,2,2,1 --quiet"],
         ["multi", "multi-stats", "listed", "world.vol", "world.orientation.vol"], ["garments.txt"]),
    ]

CASES += [
    # export's options, from the CPU in-memory .vdb.
    ("export", set(),
     ["export ../cpu-memory/out.vdb -o u8.vol --vol-type uint8 --quiet",
      "export ../cpu-memory/out.vdb -o f16.vol --vol-type float16 --orientation-vol-type uint8 "
      "--vol-bbox centres --quiet",
      "export ../cpu-memory/out.vdb -o box.vol --bbox 8,8,8,72,72,40 --sggx 0.2 --quiet",
      "export ../cpu-workdir/out.vdb -o region.vol --region 1 --work-dir ../cpu-workdir/work --quiet",
      "export ../cpu-lod2-half/out.vdb -o half.nvdb --quiet"],
     ["u8.vol", "u8.orientation.vol", "f16.vol", "f16.orientation.vol", "box.vol", "box.orientation.vol",
      "box.sggx.vol", "region.vol", "region.orientation.vol", "half.nvdb"]),
    # The dense method (the GL rasterizer into dense 3D textures): its stats
    # only. Its .vdb is left out: the values differ from run to run of the
    # same binary on llvmpipe (3 different files in 5 runs), as its fragments
    # read, compare and write voxels without atomics (shaders/dense.frag, the
    # paper's race, kept on purpose). The file is still written (listed).
    ("gl-dense", {"gl"},
     [f"voxelize {G}twill-flat.bcc -o out.vdb --backend gl --method dense --resolution 96 --quiet "
      "--stats stats.json"],
     ["stats.json"], ["out.vdb"]),
    # mpirun -np 2: in memory (the default work dir carries the regions
    # between the ranks and is removed), and in a work dir then resumed by
    # one process.
    ("mpi-cpu", {"mpi"},
     [f"mpi: voxelize {G}knit-cylinder.bcc -o out.vdb --backend cpu {R} {COMMON} {NO_LOD} --stats stats.json",
      f"mpi: voxelize {G}twill-flat.bcc -o work.vdb --backend cpu {R} {COMMON} --work-dir work --lod 1 "
      "--stats work.json"],
     ["out.vdb", "stats.json", "work.vdb", "work", "work.json"]),
    ("mpi-gl", {"mpi", "gl"},
     [f"mpi: voxelize {G}knit-cylinder.bcc -o out.vdb --backend gl {R} {COMMON} {NO_LOD} --cross-section "
      f"{G}colour.png --albedo --stats stats.json",
      f"mpi: voxelize {G}plain-cylinder.bcc -o work.vdb --backend gl {R} {COMMON} {NO_LOD} --work-dir work "
      "--stats work.json",
      copy_dir("work", "work-partial"),
      partial("work-partial"),
      f"mpi: voxelize {G}plain-cylinder.bcc -o resumed.vdb --backend gl {R} {COMMON} {NO_LOD} --work-dir "
      "work-partial --resume --stats resumed.json"],
     ["out.vdb", "stats.json", "work.vdb", "work", "work.json", "resumed.vdb", "work-partial",
      "resumed.json"]),
]


# ---------------------------------------------------------------- running

def run_all(args, skip):
    yarnvox = os.path.abspath(args.yarnvox)
    scratch = os.path.abspath(args.scratch)
    shutil.rmtree(scratch, ignore_errors=True)
    os.makedirs(scratch)
    env = dict(os.environ, OMPI_MCA_rmaps_base_oversubscribe="1")
    mpirun = [args.mpiexec, "--bind-to", "none", "--allow-run-as-root", "--oversubscribe", "--mca", "btl",
              "self,vader", "--mca", "btl_vader_single_copy_mechanism", "none", "--mca", "mpi_yield_when_idle",
              "1", "-np", "2"] if args.mpiexec else None

    def yv(cmd, cwd, mpi=False):
        argv = (mpirun if mpi else []) + [yarnvox] + cmd.split()
        t = time.monotonic()
        p = subprocess.run(argv, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
        if args.verbose:
            print(f"# {time.monotonic() - t:6.2f} s  {'mpirun ' if mpi else ''}{cmd}", file=sys.stderr)
        return p.returncode, p.stdout.decode(errors="replace")

    lines = []

    def digest(name, path, stats_varying=frozenset()):
        data = normalise(path, name, stats_varying)
        lines.append(f"{name}  {len(data)}  {hashlib.sha256(data).hexdigest()}")

    for name, cmd in GARMENTS.items():
        rc, out = yv(f"{cmd} -o {name} --quiet", scratch)
        if rc:
            raise SystemExit(f"yarnvox {cmd} failed:\n{out}")
        digest(f"garment/{name}", os.path.join(scratch, name))
    write_png(os.path.join(scratch, "colour.png"), 32)

    if "gl" not in skip:
        # A GL context: fail where none can be made, unless YV_GL_TESTS=skip.
        rc, out = yv(f"voxelize twill-flat.bcc -o gl-probe.vdb --backend gl --resolution 16 --quiet", scratch)
        os.path.exists(os.path.join(scratch, "gl-probe.vdb")) and os.remove(os.path.join(scratch, "gl-probe.vdb"))
        if rc and "no OpenGL 4.5 context" in out:
            if os.environ.get("YV_GL_TESTS") != "skip":
                raise SystemExit("no OpenGL 4.5 context on this machine (set YV_GL_TESTS=skip to skip the GL "
                                 f"runs on purpose):\n{out}")
            print("# no OpenGL 4.5 context on this machine: GL runs skipped (YV_GL_TESTS=skip)", file=sys.stderr)
            skip.add("gl")
        elif rc:
            raise SystemExit(f"the GL probe run failed:\n{out}")

    for case, needs, commands, outputs, *undigested in CASES:
        if needs & skip:
            continue
        if args.only and not re.search(args.only, case):
            continue
        d = os.path.join(scratch, case)
        os.makedirs(d)
        for c in commands:
            if callable(c):
                c(d)
                continue
            mpi = c.startswith("mpi: ")
            rc, out = yv(c[5:] if mpi else c, d, mpi)
            if rc:
                raise SystemExit(f"{case}: yarnvox {c} failed ({rc}):\n{out}")
        more = (STATS_VARYING_MPI if "mpi" in needs else set()) | (STATS_VARYING_DENSE if "dense" in case else set())
        for o in outputs:
            p = os.path.join(d, o)
            if os.path.isdir(p):
                files = sorted(os.listdir(p), key=lambda f: (not f.startswith("region-"), len(f), f))
                for f in files:
                    if f != "manifest":  # left out: see the top of this file
                        digest(f"{case}/{o}/{f}", os.path.join(p, f))
            elif os.path.exists(p):
                digest(f"{case}/{o}", p, more)
            else:
                lines.append(f"{case}/{o}  missing")
        # Anything written that the case does not list is an error of this
        # script, or an output that should not be there.
        listed = {o.split("/")[0] for o in outputs + sum(undigested, [])}
        extra = [f for f in os.listdir(d) if f not in listed]
        if extra:
            raise SystemExit(f"{case}: outputs not digested: {extra}")
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--yarnvox", required=True, help="the yarnvox binary")
    ap.add_argument("--scratch", required=True, help="a scratch folder (emptied first)")
    ap.add_argument("--mpiexec", default="", help="mpirun, for the MPI runs (left out without it)")
    ap.add_argument("--compare", help="golden file: exit 1 with a diff when any line differs")
    ap.add_argument("--only", help="only the cases whose name matches this regex (no --compare)")
    ap.add_argument("--keep", action="store_true", help="keep the scratch folder (kept anyway when a digest differs)")
    ap.add_argument("-v", "--verbose", action="store_true", help="time each command (on stderr)")
    args = ap.parse_args()
    # Notes (stderr) and results (stdout) in the order they are made, when CTest joins them.
    sys.stdout.reconfigure(line_buffering=True)
    if args.only and args.compare:
        ap.error("--only leaves cases out: no --compare with it")

    skip = set()
    if not args.mpiexec:
        print("# no --mpiexec (yarnvox built without MPI): MPI runs skipped", file=sys.stderr)
        skip.add("mpi")
    t = time.monotonic()
    lines = run_all(args, skip)
    print(f"# {len(lines)} outputs digested in {time.monotonic() - t:.1f} s", file=sys.stderr)
    if not args.compare:
        if not args.keep:
            shutil.rmtree(args.scratch)
        print("# yarnvox output digests (tests/output_digests.py, docs/same-bytes.md): NAME  BYTES  SHA-256 of the")
        print("# normalised content, one line per file the runs write" +
              (f"; skipped: {' '.join(sorted(skip))}" if skip else ""))
        print("\n".join(lines))
        return 0

    skipped_cases = {c[0] for c in CASES if c[1] & skip}
    golden = []
    for line in open(args.compare).read().splitlines():
        if not line or line.startswith("#"):
            continue
        if line.split("/")[0] in skipped_cases:
            continue
        golden.append(line)
    if skipped_cases:
        print(f"# not compared (skipped above): {' '.join(sorted(skipped_cases))}", file=sys.stderr)
    if golden == lines:
        print(f"# all {len(lines)} digests equal those of {os.path.basename(args.compare)}")
        if not args.keep:
            shutil.rmtree(args.scratch)
        return 0
    print(f"# outputs differ from {args.compare} (- golden, + this binary); the outputs are kept in {args.scratch}:")
    sys.stdout.writelines(difflib.unified_diff([l + "\n" for l in golden], [l + "\n" for l in lines],
                                               "golden", "this binary", n=0))
    return 1


if __name__ == "__main__":
    sys.exit(main())
