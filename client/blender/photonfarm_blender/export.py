"""Writes the open Blender scene as a farm scene file, with its meshes (farm mesh files)
and images beside it. Reads Blender through bpy; every mapping is a function of
convert.py."""

import json
import math
import os
import re
import shutil

import bpy
import numpy as np

from . import convert

DEFAULT_MATERIAL = "photonfarm-default"
# Image files the workers read as they are; anything else (packed, generated, other
# formats) is written out as PNG or OpenEXR.
READABLE = {".png", ".jpg", ".jpeg", ".exr", ".hdr"}


class Settings:
    """The farm's render settings that Blender has no counterpart for."""

    def __init__(self, samples_per_pixel=4, rounds=1, global_photons=200000,
                 caustic_photons=200000, photons_per_shard=100000, tile_size=32, seed=1):
        self.samples_per_pixel = samples_per_pixel
        self.rounds = rounds
        self.global_photons = global_photons
        self.caustic_photons = caustic_photons
        self.photons_per_shard = photons_per_shard
        self.tile_size = tile_size
        self.seed = seed

    @classmethod
    def of(cls, scene):
        """The settings kept on a scene by the add-on's panel (scene.photonfarm)."""
        p = getattr(scene, "photonfarm", None)
        if p is None:
            return cls()
        return cls(p.samples_per_pixel, p.rounds, p.global_photons, p.caustic_photons,
                   p.photons_per_shard, p.tile_size, p.seed)


def _read(collection, attribute, dtype, count):
    """A bpy collection's attribute for every item, flat, through foreach_get."""
    out = np.empty(count, dtype=dtype)
    collection.foreach_get(attribute, out)
    return out


def _uses_nodes(datablock):
    """Blender 5 always shades with the node tree (and deprecates use_nodes)."""
    return bpy.app.version >= (5, 0, 0) or datablock.use_nodes


def safe_name(name):
    return re.sub(r"[^A-Za-z0-9._-]+", "_", name).strip("._") or "unnamed"


class _Exporter:
    def __init__(self, scene, depsgraph, directory, settings):
        self.scene, self.depsgraph, self.directory = scene, depsgraph, directory
        self.settings = settings
        self.warnings = []
        # Blender material name (None: objects without one; ("light", name): an area
        # light's) -> farm material
        self.materials = {}
        self.textures = {}  # Blender image name -> farm texture
        self.meshes = {}  # (evaluated object name, its data's name) -> farm mesh
        self.shapes, self.lights = [], []
        self.taken = {"material": set(), "mesh": set(), "texture": set()}

    def unique(self, kind, raw):
        """A file-safe name for a material, mesh or texture that no other of its kind has
        (Blender names that differ may make the same safe name)."""
        base = name = safe_name(raw)
        n = 1
        while name in self.taken[kind]:
            n += 1
            name = f"{base}.{n}"
        self.taken[kind].add(name)
        return name

    def warn(self, text):
        self.warnings.append(text)

    # -- images ------------------------------------------------------------------------

    def texture(self, image):
        """The farm texture name of a Blender image, writing the image beside the scene."""
        if image.name in self.textures:
            return self.textures[image.name]["name"]
        name = self.unique("texture", image.name)
        os.makedirs(os.path.join(self.directory, "textures"), exist_ok=True)
        source = bpy.path.abspath(image.filepath, library=image.library) if image.filepath else ""
        ext = os.path.splitext(source)[1].lower()
        if image.source == "FILE" and not image.packed_file and ext in READABLE and os.path.isfile(source):
            relative = f"textures/{name}{ext}"
            shutil.copyfile(source, os.path.join(self.directory, relative))
        else:
            ext = ".exr" if image.is_float else ".png"
            relative = f"textures/{name}{ext}"
            copy = image.copy()
            try:
                copy.filepath_raw = os.path.join(self.directory, relative)
                copy.file_format = "OPEN_EXR" if image.is_float else "PNG"
                copy.save()
            finally:
                bpy.data.images.remove(copy)
        self.textures[image.name] = {"name": name, "path": relative,
                                     "encoding": convert.texture_encoding(image.colorspace_settings.name)}
        return name

    def image_of(self, socket):
        """The image an Image Texture node linked into socket reads, or None."""
        if not socket.is_linked:
            return None
        node = socket.links[0].from_node
        if node.type == "NORMAL_MAP":
            return self.image_of(node.inputs["Color"])
        if node.type != "TEX_IMAGE" or node.image is None:
            self.warn(f"input {socket.name!r} of {socket.node.name!r}: only an Image Texture node is read")
            return None
        wrap, warning = convert.texture_wrap(node.extension)
        if warning:
            self.warn(f"{node.image.name}: {warning}")
        name = self.texture(node.image)
        self.textures[node.image.name]["wrap"] = wrap
        return name

    # -- materials ---------------------------------------------------------------------

    def material(self, mat):
        """The farm material name of a Blender material (None: the default grey)."""
        key = mat.name if mat else None
        if key in self.materials:
            return self.materials[key]["name"]
        name = self.unique("material", mat.name if mat else DEFAULT_MATERIAL)
        farm, warnings = self.convert_material(name, mat)
        self.warnings.extend(warnings)
        self.materials[key] = farm
        return name

    def convert_material(self, name, mat):
        if mat is None:
            return convert.principled_material(name)
        surface = None
        if mat.node_tree and _uses_nodes(mat):
            outputs = [n for n in mat.node_tree.nodes if n.type == "OUTPUT_MATERIAL"]
            active = [n for n in outputs if n.is_active_output] or outputs
            if active and active[0].inputs["Surface"].is_linked:
                surface = active[0].inputs["Surface"].links[0].from_node
        if surface is None:
            return convert.principled_material(name, base_color=mat.diffuse_color,
                                               metallic=mat.metallic, roughness=mat.roughness)
        inputs = surface.inputs
        if surface.type == "BSDF_DIFFUSE" and not inputs["Color"].is_linked:
            reflectance = convert.clamp01(inputs["Color"].default_value)
            return {"name": name, "lambert": {"reflectance": convert.color(reflectance)}}, []
        if surface.type == "BSDF_DIFFUSE":
            return convert.principled_material(name, base_color=(1, 1, 1), roughness=1.0,
                                               base_color_texture=self.image_of(inputs["Color"]))
        if surface.type == "EMISSION":
            radiance = convert.scaled(inputs["Color"].default_value, inputs["Strength"].default_value)
            return {"name": name, "emissive": {"radiance": convert.color(radiance)}}, []
        if surface.type != "BSDF_PRINCIPLED":
            return convert.principled_material(name, base_color=mat.diffuse_color)[0], [
                f"material {mat.name!r}: {surface.bl_label} is not mapped; exported as its viewport colour"]
        base_texture = self.image_of(inputs["Base Color"])
        emission_texture = self.image_of(inputs["Emission Color"])
        normal_texture, normal_scale = None, 1.0
        if inputs["Normal"].is_linked and inputs["Normal"].links[0].from_node.type == "NORMAL_MAP":
            normal_map = inputs["Normal"].links[0].from_node
            normal_texture = self.image_of(inputs["Normal"])
            normal_scale = normal_map.inputs["Strength"].default_value
        return convert.principled_material(
            name,
            base_color=(1, 1, 1) if base_texture else inputs["Base Color"].default_value,
            base_color_texture=base_texture,
            metallic=inputs["Metallic"].default_value,
            roughness=inputs["Roughness"].default_value,
            transmission=inputs["Transmission Weight"].default_value,
            ior=inputs["IOR"].default_value,
            emission_color=(1, 1, 1) if emission_texture else inputs["Emission Color"].default_value,
            emission_strength=inputs["Emission Strength"].default_value,
            emission_texture=emission_texture,
            normal_texture=normal_texture, normal_scale=normal_scale)

    # -- geometry ----------------------------------------------------------------------

    def mesh(self, ob):
        """The farm mesh of an evaluated object (modifiers applied), written once however
        many instances place it; None if it has no triangles."""
        key = (ob.name, ob.data.name if ob.data else "")
        if key in self.meshes:
            return self.meshes[key]
        me = ob.to_mesh()
        try:
            self.meshes[key] = farm = self.write_mesh(ob, me)
        finally:
            ob.to_mesh_clear()
        return farm

    def write_mesh(self, ob, me):
        me.calc_loop_triangles()
        triangles = len(me.loop_triangles)
        if triangles == 0:
            return None
        corners = _read(me.loop_triangles, "loops", np.int32, 3 * triangles)
        slots = _read(me.loop_triangles, "material_index", np.int32, triangles)
        vertex_of = _read(me.loops, "vertex_index", np.int32, len(me.loops))
        co = _read(me.vertices, "co", np.float32, 3 * len(me.vertices)).reshape(-1, 3)
        normals = _read(me.corner_normals, "vector", np.float32, 3 * len(me.loops)).reshape(-1, 3)
        uvs = None
        if me.uv_layers.active:
            uvs = convert.uvs(_read(me.uv_layers.active.data, "uv", np.float32, 2 * len(me.loops)))
        name = self.unique("mesh", ob.name)
        os.makedirs(os.path.join(self.directory, "meshes"), exist_ok=True)
        parts = []
        for slot, (kept, indices) in sorted(convert.split_parts(corners, slots).items()):
            mat = ob.material_slots[slot].material if slot < len(ob.material_slots) else None
            relative = f"meshes/{name}.{slot}.farmmesh"
            with open(os.path.join(self.directory, relative), "wb") as f:
                f.write(convert.farm_mesh(co[vertex_of[kept]], normals[kept],
                                          None if uvs is None else uvs[kept], indices))
            parts.append({"path": relative, "material": self.material(mat)})
        return {"name": name, "parts": parts}

    def light(self, ob, world):
        data, name = ob.data, safe_name(ob.name)
        rgb, power = tuple(data.color), data.energy
        if data.type == "POINT":
            self.lights.append(convert.point_light(name, world, rgb, power))
        elif data.type == "SPOT":
            self.lights.append(convert.spot_light(name, world, rgb, power, data.spot_size, data.spot_blend))
        elif data.type == "SUN":
            self.lights.append(convert.sun_light(name, world, rgb, data.energy, data.angle))
        elif data.type == "AREA":
            sx = data.size
            sy = data.size_y if data.shape in ("RECTANGLE", "ELLIPSE") else data.size
            if data.shape in ("DISK", "ELLIPSE"):
                self.warn(f"area light {ob.name!r}: a {data.shape.lower()} renders as a rectangle of its size")
            material_name = self.unique("material", f"{ob.name}-emission")
            shape, material = convert.area_light(name, world, rgb, power, sx, sy, material_name)
            self.shapes.append(shape)
            self.materials[("light", material_name)] = material
            if data.spread < math.pi - 1e-6:
                self.warn(f"area light {ob.name!r}: its spread is not exported (the farm's area lights emit over the hemisphere)")
        if data.type in ("POINT", "SPOT") and data.shadow_soft_size > 0:
            self.warn(f"light {ob.name!r}: its radius is not exported (the farm's point lights are points)")

    def camera(self, width, height):
        cam_ob = self.scene.camera
        if cam_ob is None:
            raise ValueError("the scene has no active camera")
        cam = cam_ob.data
        if cam.type != "PERSP":
            raise ValueError(f"camera {cam_ob.name!r} is {cam.type.lower()}: only perspective cameras are exported")
        if cam.shift_x or cam.shift_y:
            self.warn(f"camera {cam_ob.name!r}: lens shift is not exported")
        aperture, focus = 0.0, 0.0
        if cam.dof.use_dof and cam.dof.aperture_fstop > 0:
            # The lens's focal length in scene units over twice the f-number, taking one
            # Blender unit as a metre (the camera's lens is in millimetres).
            aperture = cam.lens / 1000.0 / (2.0 * cam.dof.aperture_fstop)
            focus = cam.dof.focus_distance
            if cam.dof.focus_object is not None:
                focus = (cam.dof.focus_object.matrix_world.translation - cam_ob.matrix_world.translation).length
        world = cam_ob.evaluated_get(self.depsgraph).matrix_world
        return convert.camera(world, cam.lens, cam.sensor_width, cam.sensor_height,
                              cam.sensor_fit, width, height, aperture, focus)

    def environment(self):
        world = self.scene.world
        if world is None:
            return None
        if not (world.node_tree and _uses_nodes(world)):
            rgb = tuple(world.color)
            return {"radiance": convert.color(rgb)} if any(rgb) else None
        outputs = [n for n in world.node_tree.nodes if n.type == "OUTPUT_WORLD"]
        active = [n for n in outputs if n.is_active_output] or outputs
        if not active or not active[0].inputs["Surface"].is_linked:
            return None
        bg = active[0].inputs["Surface"].links[0].from_node
        if bg.type != "BACKGROUND":
            self.warn(f"world: {bg.bl_label} is not mapped; the world is black")
            return None
        strength = bg.inputs["Strength"].default_value
        colour = bg.inputs["Color"]
        if colour.is_linked and colour.links[0].from_node.type == "TEX_ENVIRONMENT":
            node = colour.links[0].from_node
            if node.image is None:
                return None
            if node.inputs["Vector"].is_linked:
                self.warn("world: the environment texture's vector input (a mapping) is not exported")
            return {"map": {"texture": self.texture(node.image)},
                    "radiance": convert.color((strength,) * 3),
                    "rotationDegrees": convert.ENVIRONMENT_ROTATION_DEGREES}
        if colour.is_linked:
            self.warn("world: only a colour or an Environment Texture node is read")
        rgb = convert.scaled(colour.default_value, strength)
        return {"radiance": convert.color(rgb)} if any(rgb) else None

    def run(self, name):
        r = self.scene.render
        width = max(1, r.resolution_x * r.resolution_percentage // 100)
        height = max(1, r.resolution_y * r.resolution_percentage // 100)
        if r.pixel_aspect_x != r.pixel_aspect_y:
            self.warn("non-square pixels are not exported")
        camera = self.camera(width, height)
        for inst in self.depsgraph.object_instances:
            ob = inst.object
            world = [list(row) for row in inst.matrix_world]
            if ob.type == "LIGHT":
                self.light(ob, world)
            elif ob.type in ("MESH", "CURVE", "SURFACE", "META", "FONT", "CURVES"):
                mesh = self.mesh(ob)
                if mesh is not None:
                    self.shapes.append({"name": safe_name(ob.name),
                                        "instance": {"mesh": mesh["name"],
                                                     "transform": {"matrix": convert.matrix12(world)}}})
        environment = self.environment()  # before the textures are listed: it may add one
        s = self.settings
        scene = {
            "name": name,
            "camera": camera,
            "film": {"width": width, "height": height, "tileSize": s.tile_size},
            "sampling": {"samplesPerPixel": s.samples_per_pixel, "seed": str(s.seed)},
            "photons": {"globalPhotons": str(s.global_photons), "causticPhotons": str(s.caustic_photons),
                        "photonsPerShard": str(s.photons_per_shard)},
            "progressive": {"maxRounds": s.rounds},
            "materials": list(self.materials.values()),
            "meshes": [m for m in self.meshes.values() if m is not None],
            "shapes": self.shapes,
            "lights": self.lights,
            "textures": list(self.textures.values()),
        }
        if environment:
            scene["environment"] = environment
        return scene


def export_scene(directory, settings=None, name=None):
    """Writes the context's scene, as its view layer evaluates it, to directory/NAME.json
    (NAME: the scene's name, made file-safe) with its meshes and textures beside it.
    Returns (path of the scene file, warnings)."""
    scene = bpy.context.scene
    depsgraph = bpy.context.evaluated_depsgraph_get()
    settings = settings or Settings.of(scene)
    name = name or safe_name(scene.name)
    os.makedirs(directory, exist_ok=True)
    exporter = _Exporter(scene, depsgraph, directory, settings)
    farm = exporter.run(name)
    path = os.path.join(directory, f"{name}.json")
    with open(path, "w") as f:
        json.dump(farm, f, indent=1)
    return path, exporter.warnings
