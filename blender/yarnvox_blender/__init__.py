"""File > Import > Yarn-level garment (.bcc): voxelizes the garment with the
installed yarnvox (in the background, with its progress in the status bar,
Esc to cancel) and adds it as a Volume object with a Cycles material
(docs/rendering.md, "Blender add-on"). Needs the yarnvox command line and
Python module (tools/install)."""

bl_info = {
    "name": "yarnvox: yarn-level garments",
    "author": "yarnvox",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "File > Import > Yarn-level garment (.bcc)",
    "description": "Voxelizes a yarn-level garment (BCC) into a fibre volume and imports it",
    "category": "Import-Export",
}

import os

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, StringProperty
from bpy_extras.io_utils import ImportHelper

from . import run, scene


def _yarnvox():
    try:
        import yarnvox
    except ImportError as e:
        raise RuntimeError("the yarnvox Python module is not installed (tools/install)") from e
    return yarnvox


class IMPORT_SCENE_OT_yarnvox_bcc(bpy.types.Operator, ImportHelper):
    """Voxelize a yarn-level garment (BCC) with yarnvox and import it as a volume"""

    bl_idname = "import_scene.yarnvox_bcc"
    bl_label = "Import Yarn-level Garment"
    bl_options = {"REGISTER", "UNDO"}

    filename_ext = ".bcc"
    filter_glob: StringProperty(default="*.bcc", options={"HIDDEN"})

    size_by: EnumProperty(name="Grid", items=[("RESOLUTION", "Resolution", "Voxels on the longest axis"),
                                              ("VOXEL_SIZE", "Voxel size", "Voxel edge, garment units")])
    resolution: IntProperty(name="Resolution", default=256, min=8, max=1 << 20)
    voxel_size: FloatProperty(name="Voxel size", default=0.05, min=1e-6, precision=4)
    yarn_radius: FloatProperty(name="Yarn radius", default=0.0, min=0.0, precision=4,
                               description="0: the garment file's, else estimated from where yarns touch")
    twist: FloatProperty(name="Twist", default=0.0, description="Radians per unit of yarn length")
    cross_section: EnumProperty(name="Cross-section", items=[("fibers", "Fibres", ""), ("disk", "Disk", ""),
                                                             ("PNG", "PNG file", "")])
    cross_section_png: StringProperty(name="PNG", subtype="FILE_PATH")
    albedo: BoolProperty(name="Albedo from the PNG", default=False)
    precision: EnumProperty(name="Precision", default="half",
                            items=[("half", "Half", "16-bit values: about half the bytes, the same picture"),
                                   ("float", "Float", "32-bit values")])
    lod: EnumProperty(name="Levels of detail", items=[("preview", "Preview pyramid", ""), ("0", "None", ""),
                                                      ("2", "Levels 1-2", ""), ("3", "Levels 1-3", "")])
    backend: EnumProperty(name="Backend", items=[("auto", "Auto", ""), ("gl", "GPU (OpenGL)", ""), ("cpu", "CPU", "")])
    optical_depth: FloatProperty(name="Yarn optical depth", default=10.0, min=0.0,
                                 description="Optical depth across a yarn's middle; sets the material's density")

    def draw(self, context):
        layout = self.layout
        layout.prop(self, "size_by")
        layout.prop(self, "resolution" if self.size_by == "RESOLUTION" else "voxel_size")
        layout.prop(self, "yarn_radius")
        if self.yarn_radius == 0.0 and os.path.isfile(self.filepath):
            try:
                layout.label(text="Yarn radius: %.4g (%s)" % self._radius())
            except Exception as e:  # a bad file: said when importing
                layout.label(text=str(e))
        for name in ("twist", "cross_section", "precision", "lod", "backend", "optical_depth"):
            layout.prop(self, name)
        if self.cross_section == "PNG":
            layout.prop(self, "cross_section_png")
            layout.prop(self, "albedo")

    def _radius(self):
        """The yarn radius and where it comes from, as voxelize would choose it."""
        if self.yarn_radius > 0:
            return self.yarn_radius, "given"
        yarnvox = _yarnvox()
        recorded = yarnvox.read_bcc(self.filepath)["yarn_radius"]
        if recorded > 0:
            return recorded, "from the file"
        estimate = yarnvox.estimate_yarn_radius(self.filepath)["radius"]
        if estimate <= 0:
            raise RuntimeError("no yarn radius in the file and no touching yarns to estimate it from: give one")
        return estimate, "estimated"

    def _words(self, output, radius):
        words = [self.filepath, "-o", output, "--yarn-radius", repr(radius), "--twist", repr(self.twist),
                 "--precision", self.precision, "--lod", self.lod, "--backend", self.backend]
        words += ["--resolution", str(self.resolution)] if self.size_by == "RESOLUTION" else \
            ["--voxel-size", repr(self.voxel_size)]
        if self.cross_section == "PNG":
            words += ["--cross-section", bpy.path.abspath(self.cross_section_png)] + (["--albedo"] if self.albedo else [])
        else:
            words += ["--cross-section", self.cross_section]
        return words

    def execute(self, context):
        try:
            self.radius = self._radius()[0]
            self.output = os.path.splitext(self.filepath)[0] + ".vdb"
            self.run = run.VoxelizeRun(_yarnvox().executable(), self._words(self.output, self.radius))
        except Exception as e:
            self.report({"ERROR"}, str(e).splitlines()[0] if str(e) else type(e).__name__)
            return {"CANCELLED"}
        if bpy.app.background:  # no event loop to wait in
            return self._finish(context, self.run.wait())
        context.window_manager.progress_begin(0, 1)
        self.timer = context.window_manager.event_timer_add(0.2, window=context.window)
        context.window_manager.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type == "ESC":
            self.run.cancel()
            self._end_ui(context)
            self.report({"WARNING"}, "yarnvox: cancelled, nothing imported")
            return {"CANCELLED"}
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        code = self.run.poll()
        if code is None:
            context.window_manager.progress_update(self.run.fraction)
            context.workspace.status_text_set("yarnvox: voxelizing %s, %d %% (Esc cancels)"
                                              % (os.path.basename(self.filepath), round(100 * self.run.fraction)))
            return {"PASS_THROUGH"}
        self._end_ui(context)
        return self._finish(context, code)

    def _end_ui(self, context):
        context.window_manager.event_timer_remove(self.timer)
        context.window_manager.progress_end()
        context.workspace.status_text_set(None)

    def _finish(self, context, code):
        if code != 0:
            self.report({"ERROR"}, "yarnvox: " + self.run.error())
            return {"CANCELLED"}
        meta = _yarnvox().read_metadata(self.output)
        viewport = meta.get("lod_first_level", min(meta.get("lod_levels", 0), 3))
        name = os.path.splitext(os.path.basename(self.filepath))[0]
        obj = scene.add_volume(context, name, self.output, scene.extinction(self.radius, self.optical_depth),
                               viewport, self.cross_section == "PNG" and self.albedo)
        self.report({"INFO"}, "yarnvox: imported %s as %s" % (self.output, obj.name))
        return {"FINISHED"}


def menu_import(self, context):
    self.layout.operator(IMPORT_SCENE_OT_yarnvox_bcc.bl_idname, text="Yarn-level garment (.bcc)")


def register():
    bpy.utils.register_class(IMPORT_SCENE_OT_yarnvox_bcc)
    bpy.types.TOPBAR_MT_file_import.append(menu_import)


def unregister():
    bpy.types.TOPBAR_MT_file_import.remove(menu_import)
    bpy.utils.unregister_class(IMPORT_SCENE_OT_yarnvox_bcc)
