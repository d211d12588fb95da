"""Renders a yarnvox .vdb in Blender's Cycles, on the CPU, headless.

    blender -b -P tools/render-blender.py -- IN.vdb OUT.png [options]

The .vdb becomes a Volume object with a Principled Volume material that reads
the `density` grid (or --grid, e.g. density_lod2). The grid holds the fibre
volume fraction, 0 to 1, so the material's Density is an extinction
coefficient per world unit: by default --optical-depth / h, h the file's
level-0 voxel size, so that a voxel full of fibre attenuates light crossing it
by exp(-optical depth); --sigma gives the coefficient itself (the same look at
every resolution of one garment). Level-of-detail grids hold the mean of
their children, so the same coefficient renders them with the same optical
depth. A camera frames the volume's bounding box, a sun and a dim sky light
it. docs/rendering.md (its Blender section) has the settings and the command.
"""

import argparse
import math
import os
import struct
import sys

import bpy
from mathutils import Vector


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="blender -b -P tools/render-blender.py --",
                                description="Render a yarnvox .vdb with Cycles on the CPU.")
    p.add_argument("input", help="yarnvox .vdb (density fog volume)")
    p.add_argument("output", help="PNG to write")
    p.add_argument("--grid", default="density", help="float grid to render (default: density; e.g. density_lod1)")
    p.add_argument("--optical-depth", type=float, default=3.0,
                   help="optical depth of one voxel full of fibre, across its width (default 3): Density = this / h")
    p.add_argument("--sigma", type=float, default=0.0,
                   help="extinction per world unit at fibre fraction 1 (overrides --optical-depth)")
    p.add_argument("--color", default="0.80,0.28,0.22",
                   help="single-scattering albedo, r,g,b (default 0.80,0.28,0.22), or 'albedo': the file's albedo "
                        "grid (yarnvox voxelize --albedo), linear RGB per voxel")
    p.add_argument("--anisotropy", type=float, default=0.0, help="Henyey-Greenstein g (default 0)")
    p.add_argument("--size", default="480x360", help="image width x height in pixels (default 480x360)")
    p.add_argument("--samples", type=int, default=16, help="Cycles samples per pixel (default 16)")
    p.add_argument("--threads", type=int, default=0, help="render threads (default 0: all cores)")
    p.add_argument("--seed", type=int, default=0,
                   help="Cycles' sampling seed (default 0): the same seed and settings give the same picture, another "
                        "seed the same picture with other noise")
    p.add_argument("--volume-precision", choices=("full", "half", "variable"), default="half",
                   help="how Cycles holds the grid while it renders (Blender's Volume setting, default half: "
                        "16 bits a value; full keeps the file's values as they are)")
    p.add_argument("--view", default="1.0,-1.4,0.7",
                   help="direction from the volume's centre to the camera, x,y,z (default 1.0,-1.4,0.7)")
    a = p.parse_args(argv)
    if not os.path.isfile(a.input):
        raise SystemExit(f"render-blender: {a.input}: no such file")
    if a.optical_depth <= 0 or a.sigma < 0 or a.samples < 1:
        raise SystemExit("render-blender: --optical-depth and --samples must be positive, --sigma non-negative")
    return a


def floats(text, n, what):
    values = [float(v) for v in text.split(",")]
    if len(values) != n:
        raise SystemExit(f"render-blender: {what} needs {n} comma-separated numbers, got '{text}'")
    return values


def import_volume(path, grid_name):
    volume = bpy.data.volumes.new("garment")
    volume.filepath = os.path.abspath(path)
    volume.grids.load()
    if not volume.grids.is_loaded:
        raise SystemExit(f"render-blender: {path}: Blender could not read it: {volume.grids.error_message}")
    names = [g.name for g in volume.grids]
    if grid_name not in names:
        raise SystemExit(f"render-blender: {path} has no grid '{grid_name}' (it has {', '.join(names)})")
    obj = bpy.data.objects.new("garment", volume)
    bpy.context.scene.collection.objects.link(obj)
    return obj, volume


def voxel_size(volume):
    """Level 0's voxel size: the density grid's transform (index to object space)."""
    grid = volume.grids["density"] if "density" in [g.name for g in volume.grids] else volume.grids[0]
    grid.load()
    return grid.matrix_object.to_3x3().col[0].length


def active_index_bounds(path, grid_name):
    """The active voxels' index bounds that OpenVDB's writer records in a grid's
    metadata (file_bbox_min/max), read from the file's grid headers only
    (formats/vdb-subset.md). Blender's own bounding box is the union of every
    grid's whole leaves, too loose to frame a camera with level-of-detail
    grids in the file."""
    with open(path, "rb") as f:
        def take(fmt):
            size = struct.calcsize(fmt)
            return struct.unpack("<" + fmt, f.read(size))

        def string():
            (n,) = take("I")
            return f.read(n).decode("utf-8", "replace")

        def metadata():
            items = {}
            (count,) = take("I")
            for _ in range(count):
                name, kind = string(), string()
                (size,) = take("I")
                value = f.read(size)
                if kind == "vec3i":
                    items[name] = struct.unpack("<3i", value)
            return items

        (magic,) = take("q")
        if magic != 0x56444220:
            raise SystemExit(f"render-blender: {path}: not an OpenVDB file")
        take("III")  # file format, library major and minor
        f.read(1 + 36)  # offsets flag, UUID
        metadata()
        (grids,) = take("i")
        for _ in range(grids):
            name = string().split("\x1e")[0]
            string()  # type
            string()  # instance parent
            grid_pos, _, end_pos = take("qqq")
            if name == grid_name:
                f.seek(grid_pos)
                take("I")  # compression
                meta = metadata()
                if "file_bbox_min" not in meta:
                    break
                return Vector(meta["file_bbox_min"]), Vector(meta["file_bbox_max"])
            f.seek(end_pos)
    raise SystemExit(f"render-blender: {path}: grid '{grid_name}' records no active bounds")


def world_bounds(obj, volume, path, grid_name):
    """World box of the grid's active voxels (whole voxels: index -0.5 to +0.5)."""
    lo, hi = active_index_bounds(path, grid_name)
    to_object = volume.grids[grid_name].matrix_object
    corners = [obj.matrix_world @ (to_object @ Vector((x, y, z)))
               for x in (lo.x - 0.5, hi.x + 0.5) for y in (lo.y - 0.5, hi.y + 0.5) for z in (lo.z - 0.5, hi.z + 0.5)]
    return (Vector([min(c[i] for c in corners) for i in range(3)]),
            Vector([max(c[i] for c in corners) for i in range(3)]))


def make_material(grid_name, density, color, anisotropy):
    mat = bpy.data.materials.new("yarn fibres")
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    nodes.clear()
    volume = nodes.new("ShaderNodeVolumePrincipled")
    if color == "albedo":
        # Cycles multiplies Color by the Color Attribute's grid: white leaves the grid's colour as it is.
        volume.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        volume.inputs["Color Attribute"].default_value = "albedo"
    else:
        volume.inputs["Color"].default_value = (*color, 1.0)
    volume.inputs["Density"].default_value = density
    volume.inputs["Density Attribute"].default_value = grid_name
    volume.inputs["Anisotropy"].default_value = anisotropy
    volume.inputs["Absorption Color"].default_value = (0.0, 0.0, 0.0, 1.0)  # extinction = Density exactly
    volume.inputs["Emission Strength"].default_value = 0.0
    volume.inputs["Blackbody Intensity"].default_value = 0.0
    out = nodes.new("ShaderNodeOutputMaterial")
    mat.node_tree.links.new(volume.outputs["Volume"], out.inputs["Volume"])
    return mat


def main():
    a = parse_args()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene

    obj, volume = import_volume(a.input, a.grid)
    h = voxel_size(volume)
    density = a.sigma if a.sigma > 0 else a.optical_depth / h
    volume.render.space = "WORLD"       # Density and step size in world units, whatever the object's scale
    volume.render.step_size = 0.0       # automatic: from the voxel size
    volume.render.precision = a.volume_precision.upper()
    if a.color == "albedo" and "albedo" not in [g.name for g in volume.grids]:
        raise SystemExit(f"render-blender: {a.input} has no 'albedo' grid (voxelize it with --albedo)")
    color = "albedo" if a.color == "albedo" else floats(a.color, 3, "--color")
    obj.data.materials.append(make_material(a.grid, density, color, a.anisotropy))

    volume.grids[a.grid].load()
    lo, hi = world_bounds(obj, volume, a.input, a.grid)
    centre = (lo + hi) / 2
    radius = (hi - lo).length / 2
    cam_data = bpy.data.cameras.new("camera")
    cam_data.lens_unit = "FOV"
    cam_data.angle = math.radians(35.0)
    view = Vector(floats(a.view, 3, "--view")).normalized()
    # The camera's angle spans the image's longer side; the bounding sphere
    # must fit the shorter one.
    try:
        width, height = (int(v) for v in a.size.lower().split("x"))
    except ValueError:
        raise SystemExit(f"render-blender: --size needs WIDTHxHEIGHT, got '{a.size}'")
    narrow = 2 * math.atan(math.tan(cam_data.angle / 2) * min(width, height) / max(width, height))
    distance = 1.05 * radius / math.sin(narrow / 2)
    cam_data.clip_start = max(distance - 2 * radius, distance * 1e-3)
    cam_data.clip_end = distance + 2 * radius
    camera = bpy.data.objects.new("camera", cam_data)
    camera.location = centre + view * distance
    camera.rotation_euler = (centre - camera.location).to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(camera)
    scene.camera = camera

    sun_data = bpy.data.lights.new("sun", type="SUN")
    sun_data.energy = 4.0
    sun_data.angle = math.radians(5.0)
    sun = bpy.data.objects.new("sun", sun_data)
    sun.rotation_euler = Vector((-0.6, -1.0, -1.2)).to_track_quat("-Z", "Y").to_euler()  # light from front left, above
    scene.collection.objects.link(sun)
    world = bpy.data.worlds.new("sky")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.06, 0.07, 0.09, 1.0)
    scene.world = world

    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = a.samples
    scene.cycles.seed = a.seed
    scene.cycles.use_animated_seed = False
    scene.cycles.use_adaptive_sampling = False
    # Few samples: denoise where this Blender has OpenImageDenoise.
    import _cycles
    scene.cycles.use_denoising = bool(getattr(_cycles, "with_openimagedenoise", False))
    if scene.cycles.use_denoising:
        scene.cycles.denoiser = "OPENIMAGEDENOISE"
    scene.cycles.max_bounces = 8
    scene.cycles.volume_bounces = 4
    scene.cycles.volume_max_steps = 1024
    if a.threads > 0:
        scene.render.threads_mode = "FIXED"
        scene.render.threads = a.threads
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_mode = "RGB"
    scene.render.image_settings.compression = 90
    scene.view_settings.view_transform = "Filmic"
    scene.render.filepath = os.path.abspath(a.output)
    print(f"render-blender: {a.input}: grid {a.grid}, voxel size {h:.6g}, Density {density:.6g} per unit, "
          f"bounds {tuple(round(v, 4) for v in lo)} to {tuple(round(v, 4) for v in hi)}, {width}x{height}, "
          f"{a.samples} samples, seed {a.seed}, volume precision {a.volume_precision}")
    bpy.ops.render.render(write_still=True)
    print(f"render-blender: wrote {a.output}")


main()
