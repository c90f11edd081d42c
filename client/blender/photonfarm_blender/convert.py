"""Pure conversions from Blender's conventions to the farm's scene format.

Nothing here imports bpy (only NumPy, which Blender bundles), so that every mapping is
unit-tested without Blender (client/blender/tests/test_convert.py). export.py reads the
Blender scene and calls these.

Axes: Blender is right-handed with +Z up; the farm is right-handed with +Y up (its
environment map's top row is +Y, and scenes put the floor at y = 0). A Blender point
(x, y, z) is the farm point (x, z, -y): a rotation of -90 degrees about +X, so lengths,
angles and the handedness of every triangle stay as they are.

Units: one farm unit is one Blender unit. The scene's unit scale (unit_settings.scale_length)
is not applied, so light falloff with distance is the same number in both.

Light: Blender gives lights a power in watts and a colour. The farm's radiant intensity,
irradiance and radiance are that power shared out as docs/lights.md says a light of each
kind emits it: a point light spreads P over 4 pi steradians; a spot light has the point
light's intensity inside its cone (as Cycles does: the cone masks, it does not focus); a sun
gives its strength as irradiance in W/m^2; an area light of area A radiates P = pi A L from
its front.
"""

import math
import struct

import numpy as np

# Blender (x, y, z) -> farm (x, z, -y), as a 3x3 matrix applied to column vectors.
AXES = ((1.0, 0.0, 0.0), (0.0, 0.0, 1.0), (0.0, -1.0, 0.0))

# Blender's equirectangular lookup puts +X (farm +X) in the image's middle column; the
# farm's puts -Z there, so the farm's map is turned -90 degrees about +Y to match
# (test_convert.py compares both lookups direction by direction).
ENVIRONMENT_ROTATION_DEGREES = -90.0

# The farm's bounds (proto/renderfarm/v1/scene.proto) that Blender values may exceed.
MAX_SUN_DIAMETER_DEGREES = 20.0
MAX_SPOT_DEGREES = 90.0
MAX_IOR = 10.0


def point(p):
    """A Blender point or direction in farm axes."""
    x, y, z = p
    return (float(x), float(z), -float(y))


def vec3(p):
    """A farm-axes point as the scene format's Vec3."""
    return {"x": p[0], "y": p[1], "z": p[2]}


def color(c):
    return {"r": float(c[0]), "g": float(c[1]), "b": float(c[2])}


def scaled(c, k):
    return tuple(float(v) * k for v in c[:3])


def clamp01(c):
    return tuple(min(1.0, max(0.0, float(v))) for v in c[:3])


def matrix12(world):
    """The farm Transform.matrix (12 values, row-major, last row left out) of a Blender
    world matrix (4x4 rows), expressed in farm axes: AXES * world."""
    rows = []
    for r in range(3):
        for c in range(4):
            rows.append(sum(AXES[r][k] * float(world[k][c]) for k in range(3)))
    return rows


def _column(m, c):
    return (float(m[0][c]), float(m[1][c]), float(m[2][c]))


def _normalized(v):
    n = math.sqrt(sum(x * x for x in v))
    if n == 0:
        raise ValueError("zero-length direction")
    return tuple(x / n for x in v)


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _add(a, b, k=1.0):
    return tuple(x + k * y for x, y in zip(a, b))


def vertical_fov_degrees(lens_mm, sensor_width_mm, sensor_height_mm, sensor_fit, width, height):
    """The farm's full vertical field of view for a Blender perspective camera.

    sensor_fit AUTO fits sensor_width to the larger image side; HORIZONTAL fits
    sensor_width to the width; VERTICAL fits sensor_height to the height."""
    if sensor_fit == "AUTO":
        sensor, along_width = sensor_width_mm, width >= height
    elif sensor_fit == "HORIZONTAL":
        sensor, along_width = sensor_width_mm, True
    elif sensor_fit == "VERTICAL":
        sensor, along_width = sensor_height_mm, False
    else:
        raise ValueError(f"unknown sensor fit {sensor_fit!r}")
    half = sensor / (2.0 * lens_mm)  # tan of the half-angle along the fitted side
    if along_width:
        half *= height / width
    return math.degrees(2.0 * math.atan(half))


def camera(world, lens_mm, sensor_width_mm, sensor_height_mm, sensor_fit, width, height,
           aperture_radius=0.0, focus_distance=0.0):
    """A Blender camera (it looks along its local -Z with local +Y up) as the farm's."""
    position = point(_column(world, 3))
    forward = _normalized(point(_column(world, 2)))
    up = _normalized(point(_column(world, 1)))
    out = {
        "position": vec3(position),
        "lookAt": vec3(_add(position, forward, -1.0)),
        "up": vec3(up),
        "verticalFovDegrees": vertical_fov_degrees(
            lens_mm, sensor_width_mm, sensor_height_mm, sensor_fit, width, height),
    }
    if aperture_radius > 0:
        out["apertureRadius"] = aperture_radius
        out["focusDistance"] = focus_distance
    return out


def point_light(name, world, rgb, power_watts):
    intensity = scaled(rgb, power_watts / (4.0 * math.pi))
    return {"name": name, "point": {"position": vec3(point(_column(world, 3))),
                                    "intensity": color(intensity)}}


def spot_cone_degrees(spot_size_radians, spot_blend):
    """Blender's full cone angle and blend as the farm's inner and outer half-angles: the
    blend is the share of the cone's cosine range over which the light fades."""
    outer = min(math.degrees(spot_size_radians) / 2.0, MAX_SPOT_DEGREES)
    cos_outer = math.cos(math.radians(outer))
    cos_inner = cos_outer + min(max(spot_blend, 0.0), 1.0) * (1.0 - cos_outer)
    return math.degrees(math.acos(min(1.0, cos_inner))), outer


def spot_light(name, world, rgb, power_watts, spot_size_radians, spot_blend):
    inner, outer = spot_cone_degrees(spot_size_radians, spot_blend)
    light = point_light(name, world, rgb, power_watts)
    spot = light.pop("point")
    spot["direction"] = vec3(scaled(point(_column(world, 2)), -1.0))
    spot["innerConeDegrees"] = inner
    spot["outerConeDegrees"] = outer
    light["spot"] = spot
    return light


def sun_light(name, world, rgb, strength, angle_radians):
    """A Blender sun shines along its local -Z; its angle is the disc's diameter."""
    return {"name": name, "sun": {
        "direction": vec3(scaled(point(_column(world, 2)), -1.0)),
        "irradiance": color(scaled(rgb, strength)),
        "angularDiameterDegrees": min(math.degrees(angle_radians), MAX_SUN_DIAMETER_DEGREES),
    }}


def area_light(name, world, rgb, power_watts, size_x, size_y, material):
    """A rectangular Blender area light (it emits from its local -Z side) as an emissive
    quad shape and its material. Returns (shape, material)."""
    centre = point(_column(world, 3))
    along_x = scaled(point(_column(world, 0)), size_x)
    along_y = scaled(point(_column(world, 1)), size_y)
    # cross(edge_u, edge_v) is the quad's front: cross(y, x) = -z, the side Blender lights.
    edge_u, edge_v = along_y, along_x
    area = math.sqrt(sum(c * c for c in _cross(edge_u, edge_v)))
    if area == 0:
        raise ValueError(f"area light {name!r} has no area")
    origin = _add(_add(centre, edge_u, -0.5), edge_v, -0.5)
    radiance = scaled(rgb, power_watts / (math.pi * area))
    shape = {"name": name, "material": material,
             "quad": {"origin": vec3(origin), "edgeU": vec3(edge_u), "edgeV": vec3(edge_v)}}
    return shape, {"name": material, "emissive": {"radiance": color(radiance)}}


def principled_material(name, base_color=(0.8, 0.8, 0.8), base_color_texture=None,
                        metallic=0.0, roughness=0.5, transmission=0.0, ior=1.5,
                        emission_color=(0.0, 0.0, 0.0), emission_strength=0.0,
                        emission_texture=None, normal_texture=None, normal_scale=1.0):
    """A Principled BSDF's inputs as a farm material. Returns (material, warnings).

    Transmission of at least one half on a non-metal makes smooth glass (Dielectric) of the
    same IOR tinted by the base colour; otherwise the farm's glTF-style Principled with
    the base colour, metallic, roughness, emission (colour times strength) and the
    textures that stand beside them."""
    warnings = []
    if transmission >= 0.5 and metallic < 0.5:
        if not 1.0 <= ior <= MAX_IOR:
            warnings.append(f"material {name!r}: IOR {ior:g} clamped to [1, {MAX_IOR:g}]")
        if roughness > 0.1:
            warnings.append(f"material {name!r}: rough glass renders as smooth glass")
        if base_color_texture:
            warnings.append(f"material {name!r}: the base colour texture of glass is skipped")
        dielectric = {"ior": min(MAX_IOR, max(1.0, ior)),
                      "transmittance": color(clamp01(base_color))}
        return {"name": name, "dielectric": dielectric}, warnings
    if transmission > 0:
        warnings.append(f"material {name!r}: transmission {transmission:g} below 0.5 is skipped")
    p = {"baseColor": color(clamp01(base_color)),
         "metallic": min(1.0, max(0.0, metallic)),
         "roughness": min(1.0, max(0.0, roughness))}
    emission = scaled(emission_color, emission_strength)
    if any(v > 0 for v in emission):
        p["emission"] = color(emission)
    if base_color_texture:
        p["baseColorTexture"] = {"texture": base_color_texture}
    if emission_texture and any(v > 0 for v in emission):
        p["emissionTexture"] = {"texture": emission_texture}
    if normal_texture:
        p["normalTexture"] = {"texture": normal_texture}
        p["normalScale"] = normal_scale
    return {"name": name, "principled": p}, warnings


def texture_wrap(extension):
    """An Image Texture node's extension as the farm's wrap. Returns (wrap, warning)."""
    wraps = {"REPEAT": "TEXTURE_WRAP_REPEAT", "EXTEND": "TEXTURE_WRAP_CLAMP",
             "MIRROR": "TEXTURE_WRAP_MIRROR"}
    if extension in wraps:
        return wraps[extension], None
    return "TEXTURE_WRAP_CLAMP", f"image extension {extension} renders as EXTEND"


def texture_encoding(colorspace):
    """Blender's colour space of an image as the farm's encoding: sRGB stays sRGB, and
    Non-Color data and the linear spaces are read as stored."""
    if colorspace == "sRGB":
        return "COLOR_ENCODING_SRGB"
    return "COLOR_ENCODING_LINEAR"


def uvs(blender_uvs):
    """Blender's UV v grows up the image; the farm mesh file's grows down it. An (n, 2)
    array in, an (n, 2) float32 array out."""
    out = np.array(blender_uvs, dtype=np.float32).reshape(-1, 2)
    out[:, 1] = 1.0 - out[:, 1]
    return out


def split_parts(triangle_corners, triangle_materials):
    """Groups triangles by material slot and renumbers their corners densely per group.

    triangle_corners: corner ids, three per triangle (Blender loop indices);
    triangle_materials: a material slot per triangle. Returns {slot: (corners, indices)}:
    the corner ids a part keeps (ascending) and its triangles as uint32 positions in
    corners."""
    triangles = np.asarray(triangle_corners).reshape(-1, 3)
    slots = np.asarray(triangle_materials)
    parts = {}
    for slot in np.unique(slots):
        kept, indices = np.unique(triangles[slots == slot], return_inverse=True)
        parts[int(slot)] = (kept, indices.astype(np.uint32).reshape(-1))
    return parts


def farm_mesh(positions, normals, uvs, indices):
    """The farm mesh file (docs/mesh-format.md) of (V, 3) positions, (V, 3) normals or None,
    (V, 2) farm texture coordinates or None, and (T, 3) indices."""
    positions = np.asarray(positions, dtype="<f4").reshape(-1, 3)
    indices = np.asarray(indices, dtype="<u4").reshape(-1)
    if len(positions) == 0 or len(indices) == 0 or len(indices) % 3:
        raise ValueError("a mesh needs vertices and whole triangles")
    flags = (1 if normals is not None else 0) | (2 if uvs is not None else 0)
    out = [b"FARMMESH", struct.pack("<IIQQ", 1, flags, len(positions), len(indices) // 3),
           positions.tobytes()]
    for values, width in ((normals, 3), (uvs, 2)):
        if values is not None:
            values = np.asarray(values, dtype="<f4").reshape(-1, width)
            if len(values) != len(positions):
                raise ValueError("a section's vertex count differs from the positions'")
            out.append(values.tobytes())
    out.append(indices.tobytes())
    return b"".join(out)
