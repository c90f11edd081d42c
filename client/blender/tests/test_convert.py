"""The add-on's conversions, without Blender: each against a closed form or a convention
stated by Blender or by the farm (worker/scene/environment.h, docs/mesh-format.md,
docs/lights.md)."""

import math
import random
import struct

import pytest
from sources import load

convert = load("photonfarm_blender/convert.py")

IDENTITY = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]


def translated(x, y, z, m=IDENTITY):
    out = [row[:] for row in m]
    out[0][3], out[1][3], out[2][3] = x, y, z
    return out


def rotation_x(degrees):
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    return [[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1]]


def near(a, b, tol=1e-9):
    return all(abs(x - y) <= tol for x, y in zip(a, b))


def xyz(v):
    return (v["x"], v["y"], v["z"])


@pytest.mark.parametrize("blender, farm", [
    ((0, 0, 1), (0, 1, 0)),  # Blender's up is the farm's up
    ((0, 1, 0), (0, 0, -1)),  # Blender's front view looks along +Y: the farm's -Z
    ((1, 0, 0), (1, 0, 0)),
    ((2, -3, 5), (2, 5, 3)),
])
def test_axes_turn_z_up_into_y_up(blender, farm):
    assert convert.point(blender) == tuple(float(v) for v in farm)


def test_axes_keep_handedness():
    # cross(x, y) = z before and after: triangles keep their front.
    a, b = convert.point((1, 0, 0)), convert.point((0, 1, 0))
    cross = (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
    assert cross == convert.point((0, 0, 1))


def test_matrix12_places_points_as_the_world_matrix_then_the_axes():
    world = translated(1, 2, 3, rotation_x(30))
    m = convert.matrix12(world)
    p = (0.5, -1.5, 2.0)
    placed = [sum(world[r][c] * p[c] for c in range(3)) + world[r][3] for r in range(3)]
    farm = [sum(m[4 * r + c] * p[c] for c in range(3)) + m[4 * r + 3] for r in range(3)]
    assert near(farm, convert.point(placed))


@pytest.mark.parametrize("fit, width, height, expected", [
    # 50 mm on a 36 mm sensor fitted to the width of a 4:3 image: tan(v/2) = 18/50 * 3/4.
    ("AUTO", 640, 480, 2 * math.degrees(math.atan(18 / 50 * 0.75))),
    ("HORIZONTAL", 640, 480, 2 * math.degrees(math.atan(18 / 50 * 0.75))),
    # AUTO fits the larger side: a portrait image gets the sensor width along its height.
    ("AUTO", 480, 640, 2 * math.degrees(math.atan(18 / 50))),
    ("VERTICAL", 640, 480, 2 * math.degrees(math.atan(12 / 50))),  # the 24 mm sensor height
])
def test_vertical_fov_follows_the_sensor_fit(fit, width, height, expected):
    assert convert.vertical_fov_degrees(50, 36, 24, fit, width, height) == pytest.approx(expected)


def test_camera_looks_along_its_minus_z_with_y_up():
    # Blender's camera with no rotation looks straight down (-Z) with +Y up the image.
    c = convert.camera(translated(0, 0, 10), 50, 36, 24, "AUTO", 100, 100)
    assert near(xyz(c["position"]), (0, 10, 0))
    assert near(xyz(c["lookAt"]), (0, 9, 0))
    assert near(xyz(c["up"]), (0, 0, -1))
    # Turned 90 degrees about X it looks along Blender's +Y (the farm's -Z), up +Z.
    c = convert.camera(rotation_x(90), 50, 36, 24, "AUTO", 100, 100)
    assert near(xyz(c["lookAt"]), (0, 0, -1))
    assert near(xyz(c["up"]), (0, 1, 0))


def test_point_light_spreads_its_power_over_the_sphere():
    light = convert.point_light("p", translated(1, 2, 3), (1, 0.5, 0), 100)
    i = light["point"]["intensity"]
    assert 4 * math.pi * i["r"] == pytest.approx(100)
    assert i["g"] == pytest.approx(i["r"] / 2) and i["b"] == 0
    assert near(xyz(light["point"]["position"]), (1, 3, -2))


def test_spot_cone_half_angles_and_blend():
    inner, outer = convert.spot_cone_degrees(math.radians(60), 0)
    assert (inner, outer) == (pytest.approx(30), pytest.approx(30))  # no blend: a hard edge
    inner, outer = convert.spot_cone_degrees(math.radians(60), 1)
    assert inner == pytest.approx(0, abs=1e-6)  # all blend: fades from the axis
    inner, _ = convert.spot_cone_degrees(math.radians(60), 0.5)
    assert math.cos(math.radians(inner)) == pytest.approx((1 + math.cos(math.radians(30))) / 2)
    light = convert.spot_light("s", IDENTITY, (1, 1, 1), 10, math.radians(60), 0)
    assert near(xyz(light["spot"]["direction"]), (0, -1, 0))  # Blender's -Z: down
    assert light["spot"]["intensity"]["r"] == pytest.approx(10 / (4 * math.pi))


def test_sun_shines_along_its_minus_z_with_its_strength_as_irradiance():
    sun = convert.sun_light("sun", rotation_x(90), (1, 1, 1), 3, math.radians(0.5))["sun"]
    # Turned 90 degrees about X, the sun's -Z is Blender's +Y: the farm's -Z.
    assert near(xyz(sun["direction"]), (0, 0, -1))
    assert sun["irradiance"]["r"] == 3
    assert sun["angularDiameterDegrees"] == pytest.approx(0.5)
    wide = convert.sun_light("sun", IDENTITY, (1, 1, 1), 1, math.radians(40))["sun"]
    assert wide["angularDiameterDegrees"] == convert.MAX_SUN_DIAMETER_DEGREES


def test_area_light_is_a_quad_facing_down_whose_power_is_pi_area_radiance():
    world = [[2, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 4], [0, 0, 0, 1]]  # scaled 2x along X, at z 4
    shape, material = convert.area_light("lamp", world, (1, 1, 1), 100, 1.5, 0.5, "lamp-emission")
    q = shape["quad"]
    u, v = xyz(q["edgeU"]), xyz(q["edgeV"])
    front = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
    area = math.sqrt(sum(c * c for c in front))
    assert area == pytest.approx(3 * 0.5)
    assert near([c / area for c in front], (0, -1, 0))  # the farm's down
    centre = [xyz(q["origin"])[i] + (u[i] + v[i]) / 2 for i in range(3)]
    assert near(centre, (0, 4, 0))
    radiance = material["emissive"]["radiance"]["r"]
    assert math.pi * area * radiance == pytest.approx(100)
    assert shape["material"] == material["name"] == "lamp-emission"


def test_principled_keeps_its_factors_and_textures():
    m, warnings = convert.principled_material(
        "m", base_color=(2, 0.5, -1), base_color_texture="wood", metallic=0.3, roughness=0.7,
        emission_color=(1, 0.5, 0), emission_strength=4, normal_texture="bumps", normal_scale=0.5)
    p = m["principled"]
    assert p["baseColor"] == {"r": 1, "g": 0.5, "b": 0}  # clamped to reflectances
    assert p["baseColorTexture"] == {"texture": "wood"}
    assert (p["metallic"], p["roughness"]) == (0.3, 0.7)
    assert p["emission"] == {"r": 4, "g": 2, "b": 0}
    assert p["normalTexture"] == {"texture": "bumps"} and p["normalScale"] == 0.5
    assert warnings == []


def test_principled_without_emission_emits_nothing():
    p = convert.principled_material("m", emission_color=(1, 1, 1), emission_strength=0)[0]["principled"]
    assert "emission" not in p


def test_transmissive_principled_is_glass_of_its_ior():
    m, warnings = convert.principled_material("g", base_color=(0.9, 1, 0.9), transmission=1, ior=1.45, roughness=0)
    assert m["dielectric"] == {"ior": 1.45, "transmittance": {"r": 0.9, "g": 1.0, "b": 0.9}}
    assert warnings == []
    m, warnings = convert.principled_material("g", transmission=1, ior=1.5, roughness=0.4)
    assert "dielectric" in m and any("rough glass" in w for w in warnings)
    m, warnings = convert.principled_material("g", transmission=0.2)
    assert "principled" in m and any("transmission" in w for w in warnings)


@pytest.mark.parametrize("extension, wrap, warned", [
    ("REPEAT", "TEXTURE_WRAP_REPEAT", False), ("EXTEND", "TEXTURE_WRAP_CLAMP", False),
    ("MIRROR", "TEXTURE_WRAP_MIRROR", False), ("CLIP", "TEXTURE_WRAP_CLAMP", True),
])
def test_texture_wrap(extension, wrap, warned):
    got, warning = convert.texture_wrap(extension)
    assert got == wrap and (warning is not None) == warned


def test_texture_encoding():
    assert convert.texture_encoding("sRGB") == "COLOR_ENCODING_SRGB"
    assert convert.texture_encoding("Non-Color") == "COLOR_ENCODING_LINEAR"
    assert convert.texture_encoding("Linear Rec.709") == "COLOR_ENCODING_LINEAR"


def test_uv_v_is_flipped():
    # Blender's bottom row (v = 0) is the last of the image, the farm's v = 1.
    assert convert.uvs([[0.25, 0.0], [0.75, 0.9]]).ravel().tolist() == pytest.approx([0.25, 1.0, 0.75, 0.1])


def _blender_equirect_uv(d):
    """Blender's equirectangular convention (Cycles' direction_to_equirectangular): the
    middle column looks along +X, u grows as atan2(y, x) falls, the top row is +Z; v
    turned to grow down the image as the farm's does."""
    u = -math.atan2(d[1], d[0]) / (2 * math.pi) + 0.5
    v = math.atan2(d[2], math.hypot(d[0], d[1])) / math.pi + 0.5
    return u % 1.0, 1.0 - v


def _farm_equirect_uv(w, rotation_degrees):
    """worker/scene/environment.cpp: ToMap turns w, then u = 1/2 + atan2(x, -z) / 2 pi and
    v = theta / pi from +Y."""
    c, s = math.cos(math.radians(rotation_degrees)), math.sin(math.radians(rotation_degrees))
    m = (w[0] * c - w[2] * s, w[1], w[0] * s + w[2] * c)
    u = 0.5 + math.atan2(m[0], -m[2]) / (2 * math.pi)
    v = math.acos(max(-1.0, min(1.0, m[1]))) / math.pi
    return u % 1.0, v


def test_environment_map_looks_the_same_way_as_in_blender():
    rng = random.Random(3)
    for _ in range(200):
        d = [rng.gauss(0, 1) for _ in range(3)]
        n = math.sqrt(sum(x * x for x in d))
        d = [x / n for x in d]
        bu, bv = _blender_equirect_uv(d)
        fu, fv = _farm_equirect_uv(convert.point(d), convert.ENVIRONMENT_ROTATION_DEGREES)
        assert min(abs(bu - fu), 1 - abs(bu - fu)) < 1e-9 and abs(bv - fv) < 1e-9, d


def test_split_parts_groups_by_material_and_renumbers_densely():
    corners = [0, 1, 2, 2, 3, 0, 4, 5, 6]
    parts = convert.split_parts(corners, [1, 0, 1])
    kept, indices = parts[0]
    assert kept.tolist() == [0, 2, 3] and indices.tolist() == [1, 2, 0]
    kept, indices = parts[1]
    assert kept.tolist() == [0, 1, 2, 4, 5, 6] and indices.tolist() == [0, 1, 2, 3, 4, 5]
    # Each part's triangles name the same corners as before.
    for slot, (kept, indices) in parts.items():
        mine = [t for t, s in enumerate([1, 0, 1]) if s == slot]
        assert kept[indices].tolist() == [c for t in mine for c in corners[3 * t:3 * t + 3]]


def test_farm_mesh_layout():
    positions = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
    data = convert.farm_mesh(positions, [[0, 0, 1]] * 3, [[0, 1], [1, 1], [0, 0]], [0, 1, 2])
    assert data[:8] == b"FARMMESH"
    version, flags, vertices, triangles = struct.unpack("<IIQQ", data[8:32])
    assert (version, flags, vertices, triangles) == (1, 3, 3, 1)
    assert len(data) == 32 + 12 * 3 + 12 * 3 + 8 * 3 + 12  # what the header implies
    assert struct.unpack("<3f", data[32 + 12:32 + 24]) == (1, 0, 0)
    assert struct.unpack("<2f", data[32 + 72 + 8:32 + 72 + 16]) == (1, 1)
    assert struct.unpack("<3I", data[-12:]) == (0, 1, 2)
    plain = convert.farm_mesh(positions, None, None, [0, 1, 2])
    assert struct.unpack("<I", plain[12:16])[0] == 0 and len(plain) == 32 + 36 + 12
    with pytest.raises(ValueError):
        convert.farm_mesh([[0, 0, 0]], None, None, [0, 0])
    with pytest.raises(ValueError):
        convert.farm_mesh(positions, [[0, 0, 1]], None, [0, 1, 2])
