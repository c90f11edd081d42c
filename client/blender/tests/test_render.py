"""End to end: a scene built with bpy (Blender as a Python module), exported by the
add-on installed the way users install it (a zip through Blender's add-on installer),
rendered on a real coordinator with two workers through the farm CLI, and the image
checked against what the scene must look like.

A red Lambertian cube stands on a textured plane under a 2 x 2 area light. The cube's top
sees nothing but the light and the black sky, so its radiance is analytic: rho / pi times
the irradiance of a uniform rectangle (the form factor of a parallel rectangle, Howell's
catalogue C-11), the light's radiance being its power over pi A. The plane's image has
four coloured quadrants; each must show where its texture coordinates put it. Where a
world point lands in the image is asked of Blender (world_to_camera_view), not of the
exporter."""

import json
import math
import os
import subprocess
import sys

import bpy
import pytest
from bpy_extras.object_utils import world_to_camera_view
from mathutils import Vector
from sources import load

package = load("package.py")
WIDTH, HEIGHT = 160, 120
LIGHT_POWER, LIGHT_SIZE, LIGHT_HEIGHT = 400.0, 2.0, 5.0
CUBE_TOP = 2.0
RED = (0.8, 0.05, 0.05)
# The image's quadrants, by (u < 1/2, v < 1/2) in Blender's UVs (v up): the colour each
# shows, and a point of the 10 x 10 plane inside it, clear of the cube's shadow.
# Grey and white lie symmetrically about the light, as green and blue do: the grey's
# stored 0.5 is sRGB, linear 0.214 of the white's (0.5 if the farm read it as linear).
QUADRANTS = {
    "green": ((0.0, 1.0, 0.0), (-3.5, -3.5)),
    "blue": ((0.0, 0.0, 1.0), (3.5, -3.5)),
    "grey": ((0.5, 0.5, 0.5), (-3.5, 3.5)),
    "white": ((1.0, 1.0, 1.0), (3.5, 3.5)),
}
SRGB_HALF = ((0.5 + 0.055) / 1.055) ** 2.4


@pytest.fixture(scope="module")
def addon(tmp_path_factory):
    """The add-on installed by Blender's own add-on installer (Preferences > Add-ons >
    Install from Disk) from the zip make blender-addon writes."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    zipped = package.build(str(tmp_path_factory.mktemp("addon") / "photonfarm.zip"))
    result = bpy.ops.preferences.addon_install(filepath=zipped, overwrite=True)
    assert result == {"FINISHED"}
    bpy.ops.preferences.addon_enable(module="photonfarm_blender")
    import photonfarm_blender
    assert os.path.dirname(photonfarm_blender.__file__) != package.ADDON, "the add-on was imported from the source tree"
    return photonfarm_blender


def _empty_scene():
    """Blender's factory settings, which leave add-ons off, with the add-on on again."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    assert bpy.ops.preferences.addon_enable(module="photonfarm_blender") == {"FINISHED"}
    return bpy.context.scene


def _quadrant_image(path):
    n = 64
    image = bpy.data.images.new("quadrants", n, n)
    pixels = []
    for y in range(n):  # Blender's rows go up the image, as v does
        for x in range(n):
            for name, (rgb, (px, py)) in QUADRANTS.items():
                if (x < n // 2) == (px < 0) and (y < n // 2) == (py < 0):
                    pixels.extend(rgb + (1.0,))
    image.pixels = pixels
    image.filepath_raw = str(path)
    image.file_format = "PNG"
    image.save()
    return bpy.data.images.load(str(path))


def _build_scene(tmp_path):
    scene = _empty_scene()
    scene.render.resolution_x, scene.render.resolution_y = WIDTH, HEIGHT
    scene.render.resolution_percentage = 100

    bpy.ops.mesh.primitive_plane_add(size=10)
    plane = bpy.context.object
    textured = bpy.data.materials.new("textured")
    nodes = textured.node_tree.nodes
    tex = nodes.new("ShaderNodeTexImage")
    tex.image = _quadrant_image(tmp_path / "quadrants.png")
    principled = nodes["Principled BSDF"]
    principled.inputs["Roughness"].default_value = 1.0
    textured.node_tree.links.new(tex.outputs["Color"], principled.inputs["Base Color"])
    plane.data.materials.append(textured)

    bpy.ops.mesh.primitive_cube_add(size=2, location=(0, 0, CUBE_TOP / 2))
    cube = bpy.context.object
    cube.modifiers.new("bevel", "BEVEL").width = 0.05  # exported evaluated: more than 12 triangles
    red = bpy.data.materials.new("red")
    nodes = red.node_tree.nodes
    nodes.remove(nodes["Principled BSDF"])
    diffuse = nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = RED + (1.0,)
    red.node_tree.links.new(diffuse.outputs["BSDF"], nodes["Material Output"].inputs["Surface"])
    cube.data.materials.append(red)

    light = bpy.data.lights.new("lamp", "AREA")
    light.energy, light.size, light.color = LIGHT_POWER, LIGHT_SIZE, (1, 1, 1)
    lamp = bpy.data.objects.new("lamp", light)
    lamp.location = (0, 0, LIGHT_HEIGHT)  # an area light shines down its -Z
    scene.collection.objects.link(lamp)

    cam = bpy.data.cameras.new("camera")
    cam.lens = 30
    camera = bpy.data.objects.new("camera", cam)
    camera.location = (0, -9, 7)
    camera.rotation_euler = (math.atan2(9, 7), 0, 0)  # looking at the origin
    scene.collection.objects.link(camera)
    scene.camera = camera
    scene.world = None

    settings = scene.photonfarm
    settings.samples_per_pixel, settings.rounds = 4, 1
    settings.global_photons, settings.caustic_photons, settings.photons_per_shard = 50000, 1000, 25000
    settings.tile_size = 32
    return scene


def _rectangle_form_factor(a, b):
    """From a point to a parallel a x b rectangle (in units of the height) above one of its
    corners."""
    p, q = math.sqrt(1 + a * a), math.sqrt(1 + b * b)
    return (a / p * math.atan(b / p) + b / q * math.atan(a / q)) / (2 * math.pi)


def _pixels(path):
    """The EXR's linear RGB, read through OpenImageIO's oiiotool (the farm writes a
    multi-layer file, which Blender opens only as render layers)."""
    rgb = os.path.splitext(path)[0] + "-rgb.exr"
    subprocess.run(["oiiotool", path, "--ch", "R,G,B", "-o", rgb], check=True)
    image = bpy.data.images.load(rgb)
    px = list(image.pixels)
    w, h = image.size
    assert (w, h) == (WIDTH, HEIGHT)

    def at(x, y):  # y from the image's top
        i = 4 * ((h - 1 - y) * w + x)
        return px[i:i + 3]
    return at


def _window_mean(at, scene, world_point, radius=1):
    camera_view = world_to_camera_view(scene, scene.camera, world_point)
    assert 0.05 < camera_view.x < 0.95 and 0.05 < camera_view.y < 0.95, camera_view
    cx, cy = int(camera_view.x * WIDTH), int((1 - camera_view.y) * HEIGHT)
    samples = [at(x, y) for x in range(cx - radius, cx + radius + 1) for y in range(cy - radius, cy + radius + 1)]
    return [sum(s[c] for s in samples) / len(samples) for c in range(3)]


def test_a_bpy_scene_renders_on_a_two_worker_farm(tmp_path, farm, addon):
    scene = _build_scene(tmp_path)

    lines = []
    exr, png = addon.render(str(tmp_path / "out"), farm=farm.farm, coordinator=farm.address,
                                 token=farm.token, on_line=lines.append)
    assert os.path.getsize(png) > 0
    tasks = subprocess.run([farm.farm, "tasks", lines[0], "--coordinator", farm.address],
                           env=dict(os.environ, FARM_TOKEN=farm.token), capture_output=True, text=True, check=True)
    workers = {word for word in tasks.stdout.split() if word.startswith("w-")}  # worker ids
    assert len(workers) == 2, f"the job's tasks ran on {len(workers)} workers, not 2:\n{tasks.stdout}"

    exported = (tmp_path / "out" / "scene" / "meshes").iterdir()
    cube_file = next(p for p in exported if p.name.startswith("Cube"))
    triangles = int.from_bytes(cube_file.read_bytes()[24:32], "little")
    assert triangles > 12, "the cube was exported without its bevel modifier"

    at = _pixels(exr)
    top = _window_mean(at, scene, Vector((0, 0, CUBE_TOP)))
    h = LIGHT_HEIGHT - CUBE_TOP
    half = LIGHT_SIZE / 2 / h
    irradiance = LIGHT_POWER / (math.pi * LIGHT_SIZE ** 2) * math.pi * 4 * _rectangle_form_factor(half, half)
    expected = [rho / math.pi * irradiance for rho in RED]
    print("cube top", top, "expected", expected)
    assert top[0] > 2 * top[1], f"the cube's lit top is not red: {top}"
    assert abs(top[0] - expected[0]) < 0.03 * expected[0], f"the cube's top R {top[0]:.4f}, analytic {expected[0]:.4f}"

    seen = {name: _window_mean(at, scene, Vector((x, y, 0))) for name, (_, (x, y)) in QUADRANTS.items()}
    print(seen)
    for name in ("green", "blue"):
        c = QUADRANTS[name][0].index(1.0)
        others = [seen[name][k] for k in range(3) if k != c]
        assert seen[name][c] > 4 * max(others), f"the {name} quadrant shows {seen[name]}"
    for name in ("grey", "white"):
        assert min(seen[name]) > 0.8 * max(seen[name]), f"the {name} quadrant shows {seen[name]}"
    # Within 15%: the plane's small specular lobe is the same on both.
    ratio = seen["grey"][1] / seen["white"][1]
    assert abs(ratio - SRGB_HALF) < 0.15 * SRGB_HALF, f"grey / white {ratio:.3f}, sRGB says {SRGB_HALF:.3f}"


def test_the_zip_installs_as_an_extension(tmp_path):
    """Blender 4.2+'s extension installer (Get Extensions > Install from Disk), in a Blender
    of its own: this process already has the add-on registered under its legacy name."""
    zipped = package.build(str(tmp_path / "photonfarm.zip"))
    script = (
        "import bpy\n"
        f"assert bpy.ops.extensions.package_install_files(filepath={zipped!r}, repo='user_default',"
        " enable_on_install=True) == {'FINISHED'}\n"
        "import bl_ext.user_default.photonfarm_blender as p\n"
        "assert bpy.context.scene.photonfarm.samples_per_pixel == 4\n"
        "assert hasattr(bpy.ops.photonfarm, 'render')\n"
        "print(p.__file__)\n")
    user = tmp_path / "user"
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(user), BLENDER_USER_SCRIPTS=str(user / "scripts"))
    done = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout.strip().splitlines()[-1].startswith(str(user / "extensions"))


def _node_material(name, **inputs):
    mat = bpy.data.materials.new(name)
    principled = mat.node_tree.nodes["Principled BSDF"]
    for key, value in inputs.items():
        principled.inputs[key].default_value = value
    return mat, principled


def _add_light(scene, kind, location, rotation=(0, 0, 0), **settings):
    light = bpy.data.lights.new(kind.lower(), kind)
    for key, value in settings.items():
        setattr(light, key, value)
    ob = bpy.data.objects.new(kind.lower(), light)
    ob.location, ob.rotation_euler = location, rotation
    scene.collection.objects.link(ob)


def test_every_kind_of_light_material_and_world_renders(tmp_path, farm, addon):
    """What the exporter writes for each light, material and world kind, the camera's depth
    of field and an HDR environment, is accepted by the coordinator and rendered by the
    workers."""
    scene = _empty_scene()
    scene.render.resolution_x, scene.render.resolution_y = 48, 32
    settings = scene.photonfarm
    settings.global_photons = settings.caustic_photons = settings.photons_per_shard = 5000
    settings.samples_per_pixel, settings.tile_size = 1, 16

    normal_image = bpy.data.images.new("bumps", 8, 8)
    normal_image.colorspace_settings.name = "Non-Color"
    normal_image.pixels = [0.5, 0.5, 1.0, 1.0] * 64
    glass, _ = _node_material("glass", **{"Transmission Weight": 1.0, "IOR": 1.45, "Roughness": 0.0})
    metal, bumpy = _node_material("metal", Metallic=1.0, Roughness=0.3)
    normal_map = metal.node_tree.nodes.new("ShaderNodeNormalMap")
    tex = metal.node_tree.nodes.new("ShaderNodeTexImage")
    tex.image = normal_image
    metal.node_tree.links.new(tex.outputs["Color"], normal_map.inputs["Color"])
    metal.node_tree.links.new(normal_map.outputs["Normal"], bumpy.inputs["Normal"])
    glowing, _ = _node_material("glowing", **{"Emission Color": (1, 0.5, 0.2, 1), "Emission Strength": 2.0})
    for i, mat in enumerate((glass, metal, glowing)):
        bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, location=(2 * i - 2, 0, 0.5))
        bpy.context.object.data.materials.append(mat)
    bpy.ops.mesh.primitive_plane_add(size=10)  # no material: the default grey
    # The glass sphere placed once more by a collection instance: one mesh, two shapes.
    glass_sphere = next(ob for ob in scene.objects if ob.data.materials and ob.data.materials[0] == glass)
    group = bpy.data.collections.new("group")
    group.objects.link(glass_sphere)
    instancer = bpy.data.objects.new("instancer", None)
    instancer.instance_type, instancer.instance_collection = "COLLECTION", group
    instancer.location = (0, 3, 0)
    scene.collection.objects.link(instancer)

    _add_light(scene, "POINT", (2, -2, 3), energy=200)
    _add_light(scene, "SPOT", (-2, -2, 3), (0.5, 0, 0), energy=300, spot_size=0.8, spot_blend=0.3)
    _add_light(scene, "SUN", (0, 0, 10), (0.3, 0.2, 0), energy=2, angle=0.01)
    _add_light(scene, "AREA", (0, 2, 3), shape="DISK", size=1.0, energy=100)

    sky = bpy.data.images.new("sky", 16, 8, float_buffer=True)
    sky.pixels = [0.2, 0.3, 0.5, 1.0] * 128
    scene.world = bpy.data.worlds.new("world")
    nodes = scene.world.node_tree.nodes
    env = nodes.new("ShaderNodeTexEnvironment")
    env.image = sky
    scene.world.node_tree.links.new(env.outputs["Color"], nodes["Background"].inputs["Color"])

    cam = bpy.data.cameras.new("camera")
    cam.dof.use_dof, cam.dof.aperture_fstop, cam.dof.focus_distance = True, 2.8, 8.0
    camera = bpy.data.objects.new("camera", cam)
    camera.location, camera.rotation_euler = (0, -8, 2), (math.radians(85), 0, 0)
    scene.collection.objects.link(camera)
    scene.camera = camera

    _, warnings = addon.export.export_scene(str(tmp_path / "exported"))
    assert any("disk renders as a rectangle" in w for w in warnings), warnings

    # The panel's button, with the connection in the add-on's preferences; headless, it
    # waits for the job instead of polling from a timer.
    prefs = bpy.context.preferences.addons["photonfarm_blender"].preferences
    prefs.farm_binary, prefs.coordinator, prefs.token = farm.farm, farm.address, farm.token
    settings.output_dir = str(tmp_path / "out")
    assert bpy.ops.photonfarm.render() == {"FINISHED"}
    exr = str(tmp_path / "out" / "Scene.exr")
    assert settings.status == f"done: {exr}"
    assert any(bpy.path.abspath(image.filepath) == exr for image in bpy.data.images)

    with open(tmp_path / "out" / "scene" / "Scene.json") as f:
        exported = json.load(f)
    placed = [shape["instance"]["mesh"] for shape in exported["shapes"] if "instance" in shape]
    assert placed.count(glass_sphere.name) == 2, placed
    kinds = {kind for light in exported["lights"] for kind in light if kind != "name"}
    assert kinds == {"point", "spot", "sun"}
    materials = {m["name"]: m for m in exported["materials"]}
    assert materials["glass"]["dielectric"]["ior"] == pytest.approx(1.45)
    assert materials["metal"]["principled"]["normalTexture"] == {"texture": "bumps"}
    assert materials["glowing"]["principled"]["emission"]["g"] == pytest.approx(1.0)
    assert "emissive" in materials["area-emission"]
    textures = {t["name"]: t for t in exported["textures"]}
    assert textures["bumps"]["encoding"] == "COLOR_ENCODING_LINEAR"
    assert textures["sky"]["path"].endswith(".exr")
    assert exported["environment"]["map"] == {"texture": "sky"}
    assert exported["camera"]["apertureRadius"] == pytest.approx(0.05 / (2 * 2.8))
