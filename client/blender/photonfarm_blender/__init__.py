"""photonfarm: renders the open Blender scene on a photonfarm render farm.

Render Properties > photonfarm: "Render on farm" exports the scene (export.py), submits
it with the farm CLI (farmcli.py) and shows the job's progress in the status bar and the
panel until the image comes back into an Image datablock. Headless:

    blender -b file.blend --python-expr "import photonfarm_blender; photonfarm_blender.render('/tmp/out')"

(with the add-on installed as an extension the module is bl_ext.user_default.photonfarm_blender).
"""

import os
import shutil

import bpy

from . import export, farmcli

bl_info = {
    "name": "photonfarm",
    "author": "photonfarm",
    "version": (0, 1, 0),
    "blender": (4, 2, 0),
    "location": "Properties > Render > photonfarm",
    "description": "Render the scene on a photonfarm render farm",
    "category": "Render",
}


def _preferences(context=None):
    context = context or bpy.context
    addon = context.preferences.addons.get(__package__)
    return addon.preferences if addon else None


def _farm_binary(explicit=None):
    prefs = _preferences()
    farm = explicit or (prefs.farm_binary if prefs and prefs.farm_binary else "") or shutil.which("farm")
    if not farm:
        raise farmcli.FarmError("the farm CLI was not found: set its path in the add-on's preferences or put it on PATH")
    return bpy.path.abspath(farm)


def _connection(coordinator=None, token=None):
    prefs = _preferences()
    coordinator = coordinator or (prefs.coordinator if prefs else "") or None
    token = token or (prefs.token if prefs else "") or None
    return coordinator, token


def render(out_dir, farm=None, coordinator=None, token=None, settings=None, on_line=print):
    """Exports the context's scene into out_dir/scene, renders it on the farm and downloads
    the image. Returns the paths of the EXR and the PNG preview; raises farmcli.FarmError
    if the job fails. For scripts and `blender -b`."""
    out_dir = bpy.path.abspath(out_dir)
    path, warnings = export.export_scene(os.path.join(out_dir, "scene"), settings=settings)
    for w in warnings:
        on_line(f"photonfarm: {w}")
    coordinator, token = _connection(coordinator, token)
    run = farmcli.FarmRun(_farm_binary(farm), path, coordinator, token)
    status = run.wait(on_line)
    if status != 0:
        raise run.failure(status)
    return run.fetch(out_dir, os.path.splitext(os.path.basename(path))[0])


class PhotonfarmPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    farm_binary: bpy.props.StringProperty(name="farm CLI", subtype="FILE_PATH",
                                          description="Path of the farm executable (empty: farm on PATH)")
    coordinator: bpy.props.StringProperty(name="Coordinator", description="HOST:PORT (empty: $FARM_COORDINATOR, else localhost:7070)")
    token: bpy.props.StringProperty(name="Client token", subtype="PASSWORD",
                                    description="Client token (empty: $FARM_TOKEN)")

    def draw(self, context):
        for prop in ("farm_binary", "coordinator", "token"):
            self.layout.prop(self, prop)


class PhotonfarmSettings(bpy.types.PropertyGroup):
    output_dir: bpy.props.StringProperty(name="Output", subtype="DIR_PATH", default="//farm/")
    samples_per_pixel: bpy.props.IntProperty(name="Samples per pixel", default=4, min=1, max=65536)
    rounds: bpy.props.IntProperty(name="Progressive rounds", default=1, min=1, max=1000)
    # At least 1000: the farm reads 0 as its default (200,000); a scene without diffuse or
    # specular surfaces gets no such map anyway (farm plan says why).
    global_photons: bpy.props.IntProperty(name="Global photons", default=200000, min=1000, max=50000000)
    caustic_photons: bpy.props.IntProperty(name="Caustic photons", default=200000, min=1000, max=50000000)
    photons_per_shard: bpy.props.IntProperty(name="Photons per task", default=100000, min=1000, max=10000000)
    tile_size: bpy.props.IntProperty(name="Tile size", default=32, min=8, max=256)
    seed: bpy.props.IntProperty(name="Seed", default=1, min=0)
    status: bpy.props.StringProperty(name="Status")


class PHOTONFARM_OT_render(bpy.types.Operator):
    """Export the scene, render it on the farm and load the image"""
    bl_idname = "photonfarm.render"
    bl_label = "Render on farm"

    _timer = None
    _run = None

    def execute(self, context):
        settings = context.scene.photonfarm
        self._out_dir = bpy.path.abspath(settings.output_dir)
        try:
            path, warnings = export.export_scene(os.path.join(self._out_dir, "scene"))
            for w in warnings:
                self.report({"WARNING"}, w)
            coordinator, token = _connection()
            self._run = farmcli.FarmRun(_farm_binary(), path, coordinator, token)
        except (ValueError, OSError, farmcli.FarmError) as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        self._job_name = os.path.splitext(os.path.basename(path))[0]
        if bpy.app.background:  # blender -b, bpy as a module: no event loop to poll from
            return self._end(context, self._run.wait(on_line=print))
        wm = context.window_manager
        self._timer = wm.event_timer_add(0.25, window=context.window)
        wm.progress_begin(0, 1)
        wm.modal_handler_add(self)
        settings.status = "submitting"
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type == "ESC":
            self._run.cancel()
            self._stop_timer(context)
            context.scene.photonfarm.status = "cancelled"
            return {"CANCELLED"}
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        status = self._run.poll()
        context.window_manager.progress_update(self._run.fraction)
        context.scene.photonfarm.status = self._run.last_line
        for area in context.screen.areas if context.screen else ():
            area.tag_redraw()
        if status is None:
            return {"RUNNING_MODAL"}
        self._stop_timer(context)
        return self._end(context, status)

    def _stop_timer(self, context):
        wm = context.window_manager
        wm.event_timer_remove(self._timer)
        wm.progress_end()

    def _end(self, context, status):
        """Once the CLI has ended with status: fetches the image and opens it."""
        settings = context.scene.photonfarm
        try:
            if status != 0:
                raise self._run.failure(status)
            exr, _ = self._run.fetch(self._out_dir, self._job_name)
        except farmcli.FarmError as e:
            self.report({"ERROR"}, str(e))
            settings.status = str(e).splitlines()[0]
            return {"CANCELLED"}
        image = bpy.data.images.load(exr, check_existing=True)
        image.reload()
        for area in context.screen.areas if context.screen else ():
            if area.type == "IMAGE_EDITOR":
                area.spaces.active.image = image
        self.report({"INFO"}, f"farm image: {exr}")
        settings.status = f"done: {exr}"
        return {"FINISHED"}


class PHOTONFARM_OT_export(bpy.types.Operator):
    """Write the scene as a farm scene file with its meshes and textures"""
    bl_idname = "photonfarm.export"
    bl_label = "Export farm scene"

    directory: bpy.props.StringProperty(subtype="DIR_PATH")

    def invoke(self, context, event):
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def execute(self, context):
        try:
            path, warnings = export.export_scene(bpy.path.abspath(self.directory))
        except (ValueError, OSError) as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        for w in warnings:
            self.report({"WARNING"}, w)
        self.report({"INFO"}, f"wrote {path}")
        return {"FINISHED"}


class PHOTONFARM_PT_render(bpy.types.Panel):
    bl_label = "photonfarm"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"

    def draw(self, context):
        settings = context.scene.photonfarm
        layout = self.layout
        for prop in ("output_dir", "samples_per_pixel", "rounds", "global_photons",
                     "caustic_photons", "photons_per_shard", "tile_size", "seed"):
            layout.prop(settings, prop)
        layout.operator(PHOTONFARM_OT_render.bl_idname, icon="RENDER_STILL")
        layout.operator(PHOTONFARM_OT_export.bl_idname, icon="EXPORT")
        if settings.status:
            layout.label(text=settings.status)


_classes = (PhotonfarmPreferences, PhotonfarmSettings, PHOTONFARM_OT_render,
            PHOTONFARM_OT_export, PHOTONFARM_PT_render)


def register():
    for cls in _classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.photonfarm = bpy.props.PointerProperty(type=PhotonfarmSettings)


def unregister():
    del bpy.types.Scene.photonfarm
    for cls in reversed(_classes):
        bpy.utils.unregister_class(cls)
