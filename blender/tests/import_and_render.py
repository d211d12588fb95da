"""The add-on, headless: installed from its zip and enabled, it imports a
generated garment at two resolutions; each lands where the garment is, and
Cycles renders them alike (the density scale follows the yarn, not the
voxel size), while the voxel-size rule's density would not. A damaged garment
is one error line with nothing added to the scene. Any failure exits 1.

    blender -b --factory-startup --python-use-system-env -P import_and_render.py -- --zip ZIP --scratch DIR
"""

import argparse
import os
import shutil
import subprocess
import sys
import time
import traceback

import bpy
import numpy as np
from mathutils import Vector


def render_mean(path):
    bpy.context.scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(path)
    pixels = np.array(image.pixels[:]).reshape(-1, 4)[:, :3]
    bpy.data.images.remove(image)
    return float(pixels.mean())


def set_up_render(centre, half):
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 8
    scene.cycles.use_adaptive_sampling = False
    scene.cycles.use_denoising = False
    scene.render.resolution_x, scene.render.resolution_y = 48, 48
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "PNG"
    scene.view_settings.view_transform = "Standard"
    scene.world = bpy.data.worlds.new("bright")
    scene.world.use_nodes = True
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (1, 1, 1, 1)
    camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    camera.data.type = "ORTHO"
    camera.data.ortho_scale = 2.4 * max(half[0], half[1])
    camera.location = (centre[0], centre[1], centre[2] + 10 * max(half))  # looking down -z
    scene.collection.objects.link(camera)
    scene.camera = camera


def check(condition, what):
    if not condition:
        raise AssertionError(what)
    print("ok:", what)


def main(args):
    import yarnvox  # the module of this build (PYTHONPATH)

    shutil.rmtree(args.scratch, ignore_errors=True)
    os.makedirs(args.scratch)
    bpy.ops.preferences.addon_install(filepath=args.zip)
    bpy.ops.preferences.addon_enable(module="yarnvox_blender")
    check(hasattr(bpy.ops.import_scene, "yarnvox_bcc"), "the add-on's importer is registered")
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)

    garment = os.path.join(args.scratch, "coarse.bcc")
    yarnvox.generate(garment, pattern="plain", shape="flat", crossings=64, seed=2)
    shutil.copy(garment, os.path.join(args.scratch, "fine.bcc"))
    points = np.concatenate(yarnvox.read_bcc(garment)["yarns"])
    lo, hi = points.min(axis=0), points.max(axis=0)
    centre, half = (lo + hi) / 2, (hi - lo) / 2

    # Translucent yarns (optical depth 1), where brightness follows the density.
    imported = {}
    for name, resolution in (("coarse", 40), ("fine", 80)):
        bpy.ops.import_scene.yarnvox_bcc(filepath=os.path.join(args.scratch, name + ".bcc"), resolution=resolution,
                                         backend="cpu", optical_depth=1.0, lod="preview")
        obj = bpy.data.objects[name]
        check(obj.type == "VOLUME" and obj.data.filepath.endswith(name + ".vdb"), f"{name}: a Volume object of the .vdb")
        obj.data.grids.load()
        check(obj.data.grids.find("density") >= 0, f"{name}: its density grid loads")
        # In place: the object at the identity, so the grid's own transform puts it in garment units...
        check(np.allclose(np.array(obj.matrix_world), np.eye(4)), f"{name}: the object adds no transform")
        box = np.array([Vector(c) for c in obj.bound_box])  # whole leaves of every grid: loose
        check(np.all(box.min(axis=0) <= lo) and np.all(box.max(axis=0) >= hi), f"{name}: its bounds hold the garment")
        # ...where the fibre lies around the yarns' curves, within a yarn radius and two voxels.
        dense = yarnvox.read_volume(obj.data.filepath)
        m, n = dense["index_to_world"], np.array(dense["density"].shape)
        first = (m @ np.array([*dense["origin"], 1.0]))[:3]
        last = (m @ np.array([*(np.array(dense["origin"]) + n - 1), 1.0]))[:3]
        margin = 0.3 + 2 * dense["voxel_size"]  # `yarnvox gen`'s radius
        check(np.all(np.abs(first - (lo - 0.3)) < margin) and np.all(np.abs(last - (hi + 0.3)) < margin),
              f"{name}: its fibre spans the garment ({first}..{last} for {lo}..{hi})")
        imported[name] = obj

    set_up_render(centre, half)
    means = {}
    for name, obj in imported.items():
        for other in imported.values():
            other.hide_render = other is not obj
        means[name] = render_mean(os.path.join(args.scratch, name + ".png"))
    background = 1.0
    dark = {name: background - m for name, m in means.items()}
    print("mean brightness:", means)
    check(dark["coarse"] > 0.05, "the garment darkens the bright background")
    check(abs(dark["fine"] - dark["coarse"]) < 0.12 * dark["coarse"], "two resolutions render alike")

    # The voxel-size rule (Density = depth / h) would double the fine one's density: visibly darker.
    principled = [n for n in imported["fine"].data.materials[0].node_tree.nodes if n.type == "PRINCIPLED_VOLUME"]
    for n in principled:
        n.inputs["Density"].default_value *= 2
    doubled = background - render_mean(os.path.join(args.scratch, "fine-doubled.png"))
    check(doubled > dark["fine"] + 0.24 * dark["coarse"], f"a doubled density renders darker ({doubled:.3f})")

    # A damaged garment: one error line, nothing added.
    bad = os.path.join(args.scratch, "damaged.bcc")
    with open(bad, "wb") as f:
        f.write(b"BCC\x44" + b"\0" * 20)
    before = (len(bpy.data.objects), len(bpy.data.volumes), len(bpy.data.materials))
    try:
        bpy.ops.import_scene.yarnvox_bcc(filepath=bad, resolution=32)
        raise AssertionError("a damaged garment was imported")
    except RuntimeError as e:
        message = str(e).strip()
        print("refused:", message)
        check("damaged.bcc" in message and len(message.splitlines()) == 1, "a damaged garment is one error line")
    check((len(bpy.data.objects), len(bpy.data.volumes), len(bpy.data.materials)) == before, "nothing was added")
    check(not os.path.exists(os.path.join(args.scratch, "damaged.vdb")), "no .vdb was written")

    check_escape_cancels(args.scratch, yarnvox)


class _Event:
    def __init__(self, kind):
        self.type = kind


class _Interface:
    """What modal() needs of the operator beyond its run, without a window
    (there is none headless): the interface teardown and the reports."""

    def __init__(self, run):
        self.run, self.reports, self.ui_ended = run, [], False

    def _end_ui(self, context):
        self.ui_ended = True

    def report(self, kind, text):
        self.reports.append((kind, text))


def check_escape_cancels(scratch, yarnvox):
    """Esc while the run goes: the operator's modal handler (as Blender calls
    it; headless there is no event loop, so the test calls it) stops yarnvox
    part-way, nothing is imported and nothing is left on the disk."""
    import yarnvox_blender
    from yarnvox_blender import run

    garment = os.path.join(scratch, "large.bcc")
    yarnvox.generate(garment, pattern="knit", shape="cylinder", crossings=6000, seed=4)
    output = os.path.join(scratch, "large.vdb")
    words = [garment, "-o", output, "--backend", "cpu", "--resolution", "384", "--fragment-budget", "200000"]
    started = run.VoxelizeRun(yarnvox.executable(), words)
    while started.poll() is None and started.fraction == 0.0:  # its first region done: part-way
        time.sleep(0.05)
    check(started.process.poll() is None, "the run was still going when Esc came (part-way)")
    before = (len(bpy.data.objects), len(bpy.data.volumes), len(bpy.data.materials))
    operator = _Interface(started)
    result = yarnvox_blender.IMPORT_SCENE_OT_yarnvox_bcc.modal(operator, bpy.context, _Event("ESC"))
    check(result == {"CANCELLED"}, "Esc ends the import (CANCELLED)")
    check(operator.ui_ended and operator.reports and "cancelled" in operator.reports[0][1],
          f"the progress is taken down and one line says so ({operator.reports})")
    check(started.process.returncode not in (None, 0), f"yarnvox stopped part-way (exit {started.process.returncode})")
    check(started.fraction < 1.0, f"before the end ({started.fraction:.2f} of the regions)")
    check((len(bpy.data.objects), len(bpy.data.volumes), len(bpy.data.materials)) == before, "nothing was imported")
    left = [n for n in os.listdir(scratch) if n.startswith("large.vdb")]
    check(not left, f"nothing was left on the disk ({left})")


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--zip", required=True)
    parser.add_argument("--scratch", required=True)
    try:
        main(parser.parse_args(sys.argv[sys.argv.index("--") + 1:]))
    except BaseException:
        traceback.print_exc()
        sys.stdout.flush()
        os._exit(1)  # blender -b -P exits 0 after a script's exception otherwise
    sys.stdout.flush()
    os._exit(0)
