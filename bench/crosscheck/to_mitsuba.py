"""A farm scene file (proto/renderfarm/v1/scene.proto, canonical JSON, as `farm import`
writes it) as a Mitsuba 3 scene dictionary, for the cross-check of issue 13's
acceptance 4. It translates what the cross-check's scenes use and refuses the rest by name
rather than rendering something else:

  camera        perspective, vertical field of view (a thin lens is refused)
  film          hdrfilm of the same size, box pixel filter (the farm's pixel is a box)
  meshes        each part of a farm mesh file (docs/mesh-format.md) written as a binary PLY
                (positions, normals, texture coordinates: glTF's v, which grows downwards,
                is what Mitsuba's bitmap lookups use), placed per instance by its matrix
  triangles     inline triangles as a PLY of their own (flat: no normals)
  quad          `rectangle` mapped onto the parallelogram, its normal cross(edge_u, edge_v)
  sphere        `sphere`
  principled    Mitsuba's `principled` (metallic, roughness, specular 0.5: F0 = 0.04),
                base colour from a `bitmap` (sRGB for 8-bit images unless the texture says
                linear) or a constant; two-sided, as the farm shades either face
  lambert       `diffuse`, two-sided as the farm's
  mirror        `conductor` with no Fresnel (material "none") of the same reflectance
  dielectric    `dielectric` of the same index (outside 1) and transmittance
  emissive      an `area` emitter of the same radiance (front side only) on a two-sided
                `diffuse` BSDF of its reflectance (black if it has none)
  environment   `envmap` rotated so that its pixels face the same directions as the farm's
                (docs/lights.md: the middle column looks along -Z, u = 0.75 along +X, while
                Mitsuba's u = 0 looks along -Z and 0.25 along +X: 180 degrees about +Y,
                plus the scene's rotation_degrees), or `constant` for a plain radiance
  sun           `directional` of the same irradiance (a delta sun; a disc is refused)
  point         `point` of the same intensity
  medium        Scene.medium: a `homogeneous` medium (sigma_t the density, or sigma_a +
                sigma_s per channel with albedo sigma_s / sigma_t; `hg` phase of the same g,
                positive forwards in both) inside a `sphere` of `null` BSDF, the farm's ball
                (docs/media.md; `medium_ball` below), vacuum outside; the sensor in it when
                the camera is inside the ball. Mitsuba changes a ray's medium only at a
                shape that names one, so the walls inside the ball leave rays in the fog
  interior      Shape.interior_medium: the shape's `interior` medium, its `exterior` the
                scene's medium (every shape lies inside the ball) or vacuum without one
  integrator    `path`, or `volpath` (the same depths) when the scene has any medium; the
                camera is taken to be in no shape's interior, as the farm takes it
"""

import copy
import json
import struct
from pathlib import Path

import numpy as np

FLAG_NORMALS, FLAG_UVS, FLAG_TANGENTS = 1, 2, 4


class Unsupported(Exception):
    """Something in the scene this translation does not carry over."""


def read_farm_mesh(path):
    """Positions, normals (or None), texture coordinates (or None) and triangles of a farm
    mesh file."""
    data = Path(path).read_bytes()
    magic, version, flags, nv, nt = struct.unpack_from("<8sIIQQ", data, 0)
    if magic != b"FARMMESH" or version != 1:
        raise Unsupported(f"{path}: not a farm mesh file of version 1")
    off = 32

    def take(count, width, dtype):
        nonlocal off
        arr = np.frombuffer(data, dtype, count * width, off).reshape(count, width)
        off += arr.nbytes
        return arr

    pos = take(nv, 3, "<f4")
    nrm = take(nv, 3, "<f4") if flags & FLAG_NORMALS else None
    uv = take(nv, 2, "<f4") if flags & FLAG_UVS else None
    if flags & FLAG_TANGENTS:
        take(nv, 4, "<f4")  # Mitsuba has no normal maps here; the cross-check's scenes have none
    tri = take(nt, 3, "<u4")
    return pos, nrm, uv, tri


def write_ply(path, pos, nrm, uv, tri):
    props = [("x", pos[:, 0]), ("y", pos[:, 1]), ("z", pos[:, 2])]
    if nrm is not None:
        props += [("nx", nrm[:, 0]), ("ny", nrm[:, 1]), ("nz", nrm[:, 2])]
    if uv is not None:
        props += [("u", uv[:, 0]), ("v", uv[:, 1])]
    header = ["ply", "format binary_little_endian 1.0", f"element vertex {len(pos)}"]
    header += [f"property float {name}" for name, _ in props]
    header += [f"element face {len(tri)}", "property list uchar uint vertex_indices", "end_header", ""]
    verts = np.column_stack([col for _, col in props]).astype("<f4")
    faces = np.zeros(len(tri), dtype=[("n", "u1"), ("i", "<u4", 3)])
    faces["n"], faces["i"] = 3, tri
    Path(path).write_bytes("\n".join(header).encode() + verts.tobytes() + faces.tobytes())


def vec(v, *keys):
    return [float(v.get(k, 0.0)) for k in keys]


def rgb(c):
    return {"type": "rgb", "value": vec(c, "r", "g", "b")}


def texture_of(scene, root, ref):
    tex = next(t for t in scene.get("textures", []) if t["name"] == ref["texture"])
    wrap = {"TEXTURE_WRAP_CLAMP": "clamp", "TEXTURE_WRAP_MIRROR": "mirror"}.get(tex.get("wrap"), "repeat")
    raw = {"COLOR_ENCODING_LINEAR": True, "COLOR_ENCODING_SRGB": False}.get(tex.get("encoding"), False)
    return {"type": "bitmap", "filename": str(root / tex["path"]), "raw": raw, "wrap_mode": wrap, "filter_type": "bilinear"}


def twosided_diffuse(reflectance):
    return {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": rgb(reflectance)}}


def bsdf_of(scene, root, material):
    if "lambert" in material:
        return twosided_diffuse(material["lambert"]["reflectance"])
    if "emissive" in material:
        return twosided_diffuse(material["emissive"].get("reflectance", {}))
    if "mirror" in material:
        return {"type": "twosided", "bsdf": {"type": "conductor", "material": "none",
                                             "specular_reflectance": rgb(material["mirror"]["reflectance"])}}
    if "dielectric" in material:
        d = material["dielectric"]
        return {"type": "dielectric", "int_ior": float(d.get("ior", 1.5)), "ext_ior": 1.0,
                "specular_transmittance": rgb(d.get("transmittance", {"r": 1, "g": 1, "b": 1}))}
    if "principled" not in material:
        raise Unsupported(f"material {material['name']!r}: only principled, lambert, emissive, mirror and "
                          "dielectric are translated")
    p = material["principled"]
    for field in ("metallicRoughnessTexture", "normalTexture", "emission", "emissionTexture", "transparency"):
        if field in p:
            raise Unsupported(f"material {material['name']!r}: principled.{field} is not translated")
    if p.get("alphaMode") == "ALPHA_MODE_MASK":
        raise Unsupported(f"material {material['name']!r}: alpha cut-outs are not translated")
    base = rgb(p.get("baseColor", {}))
    if "baseColorTexture" in p:
        if base["value"] != [1.0, 1.0, 1.0]:
            raise Unsupported(f"material {material['name']!r}: a base colour factor times a texture is not translated")
        base = texture_of(scene, root, p["baseColorTexture"])
    return {"type": "twosided", "bsdf": {"type": "principled", "base_color": base, "metallic": float(p.get("metallic", 0.0)),
                                         "roughness": float(p.get("roughness", 0.0)), "specular": 0.5}}


def matrix_of(mi, transform):
    if not transform:
        return mi.ScalarTransform4f()
    if set(transform) != {"matrix"}:
        raise Unsupported("only Transform.matrix is translated")
    m = [float(x) for x in transform["matrix"]]
    return mi.ScalarTransform4f([m[0:4], m[4:8], m[8:12], [0, 0, 0, 1]])


def emitter_of(material):
    """The area emitter of an emissive material, else None."""
    if "emissive" not in material:
        return None
    return {"type": "area", "radiance": rgb(material["emissive"]["radiance"])}


def geometry_of(mi, shape, ply_path):
    """The Mitsuba shape of a farm shape's sphere, quad or inline triangles (PLY at ply_path),
    without its BSDF; None for the other kinds."""
    if "sphere" in shape:
        s = shape["sphere"]
        return {"type": "sphere", "center": vec(s["center"], "x", "y", "z"), "radius": float(s["radius"])}
    if "quad" in shape:
        q = shape["quad"]
        o, u, v = (np.array(vec(q[k], "x", "y", "z")) for k in ("origin", "edgeU", "edgeV"))
        n = np.cross(u, v)
        n /= np.linalg.norm(n)
        c = o + (u + v) / 2
        # The rectangle is [-1, 1]^2 at z = 0 facing +z: its corners map onto the quad's and
        # its normal onto cross(edge_u, edge_v).
        m = np.column_stack([u / 2, v / 2, n, c])
        return {"type": "rectangle", "to_world": mi.ScalarTransform4f(np.vstack([m, [0, 0, 0, 1]]).tolist())}
    if "triangles" in shape:
        t = shape["triangles"]
        pos = np.array([vec(p, "x", "y", "z") for p in t["positions"]], dtype="<f4")
        tri = np.array(t["indices"], dtype="<u4").reshape(-1, 3)
        write_ply(ply_path, pos, None, None, tri)
        return {"type": "ply", "filename": str(ply_path), "face_normals": True}
    return None


def medium_of(medium):
    """Mitsuba's homogeneous medium of a farm Medium (albedo and density, or sigma_a and
    sigma_s per channel)."""
    if "albedo" in medium:
        a = medium["albedo"]
        albedo, sigma_t = rgb(a["albedo"]), float(a.get("density", 0.0))
    elif "sigma" in medium:
        s = medium["sigma"]
        sa, ss = (np.array(vec(s.get(k, {}), "r", "g", "b")) for k in ("sigmaA", "sigmaS"))
        st = sa + ss
        # volpath's spectral sampling gives NaN in a channel of no extinction beside others
        # that have some: that channel gets 1e-9 of the largest, a transmittance that differs
        # from 1 by 1e-9 over the medium's mean free path.
        if st.max() > 0:
            st = np.maximum(st, 1e-9 * st.max())
        albedo = {"type": "rgb", "value": np.divide(ss, st, out=np.zeros(3), where=st > 0).tolist()}
        sigma_t = {"type": "rgb", "value": st.tolist()}
    else:
        raise Unsupported("a medium with neither sigma nor albedo")
    return {"type": "homogeneous", "albedo": albedo, "sigma_t": sigma_t,
            "phase": {"type": "hg", "g": float(medium.get("g", 0.0))}}


def scene_bounds(scene, root):
    """The axis-aligned bounds (lo, hi) of every shape of a farm scene as the worker computes
    them (worker/scene/shapes.cpp BoundsOf): a sphere's box, a quad's four corners, the
    vertices of inline triangles, and for an instance the eight corners of its mesh's box
    placed by its matrix."""
    points = []
    meshes = {m["name"]: m for m in scene.get("meshes", [])}
    for n, shape in enumerate(scene.get("shapes", [])):
        if "sphere" in shape:
            c, r = np.array(vec(shape["sphere"]["center"], "x", "y", "z")), float(shape["sphere"]["radius"])
            points += [c - r, c + r]
        elif "quad" in shape:
            q = shape["quad"]
            o, u, v = (np.array(vec(q[k], "x", "y", "z")) for k in ("origin", "edgeU", "edgeV"))
            points += [o, o + u, o + v, o + u + v]
        elif "triangles" in shape:
            points += [np.array(vec(p, "x", "y", "z")) for p in shape["triangles"]["positions"]]
        elif "instance" in shape:
            inst = shape["instance"]
            pos = np.concatenate([read_farm_mesh(root / part["path"])[0] for part in meshes[inst["mesh"]]["parts"]])
            lo, hi = pos.min(axis=0).astype(np.float64), pos.max(axis=0).astype(np.float64)
            m = np.array([float(x) for x in inst.get("transform", {}).get("matrix", [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0])])
            m = m.reshape(3, 4)
            for corner in range(8):
                p = np.where([corner & 1, corner & 2, corner & 4], hi, lo)
                points.append(m[:, :3] @ p + m[:, 3])
        else:
            raise Unsupported(f"shapes[{n}]: the bounds of this kind of shape are not computed")
    points = np.array(points)
    return points.min(axis=0), points.max(axis=0)


def medium_ball(scene, root):
    """Centre and radius of the ball Scene.medium fills: the sphere about the shapes' bounds
    (its centre the box's, its radius half the diagonal) with the margin of
    worker/scene/lights.cpp DistantDisc::Around."""
    lo, hi = scene_bounds(scene, root)
    centre = (lo + hi) / 2
    radius = np.linalg.norm(hi - lo) / 2 * 1.01 + 1e-4 * (1 + np.max(np.abs(centre)))
    return centre, float(radius)


def add_media(out, scene, root):
    """Puts the scene's medium (its ball) and the shapes' interior media into the Mitsuba
    dictionary `out`, whose shapes are keyed shape{n} or shape{n}_{part}, and switches the
    integrator to volpath when there is any."""
    interiors = {n: s["interiorMedium"] for n, s in enumerate(scene.get("shapes", [])) if "interiorMedium" in s}
    if "medium" not in scene and not interiors:
        return
    out["integrator"]["type"] = "volpath"
    outside = None
    if "medium" in scene:
        # Declared once at the top and referred to by id: the ball's interior, the sensor's
        # medium and every interior medium's exterior are then one object.
        out["scene-medium"] = medium_of(scene["medium"])
        outside = {"type": "ref", "id": "scene-medium"}
        centre, radius = medium_ball(scene, root)
        out["scene-medium-ball"] = {"type": "sphere", "center": centre.tolist(), "radius": radius,
                                    "bsdf": {"type": "null"}, "interior": dict(outside)}
        camera = np.array(vec(scene["camera"]["position"], "x", "y", "z"))
        if np.linalg.norm(camera - centre) < radius:
            out["sensor"]["medium"] = dict(outside)
    for n, medium in interiors.items():
        out[f"medium{n}"] = medium_of(medium)
        keys = [k for k in out if k == f"shape{n}" or k.startswith(f"shape{n}_")]
        if not keys:
            raise Unsupported(f"shapes[{n}].interior_medium: the shape was not translated")
        for key in keys:
            out[key]["interior"] = {"type": "ref", "id": f"medium{n}"}
            if outside:
                out[key]["exterior"] = dict(outside)


def mitsuba_scene(mi, scene_path, work_dir, spp, seed=0):
    """The Mitsuba scene dictionary of the farm scene at scene_path, and the farm material
    of each of its shapes (by key); PLY files go in work_dir."""
    scene_path = Path(scene_path)
    root = scene_path.parent
    scene = json.loads(scene_path.read_text())
    work_dir = Path(work_dir)
    work_dir.mkdir(parents=True, exist_ok=True)
    cam, film = scene["camera"], scene["film"]
    if cam.get("apertureRadius", 0):
        raise Unsupported("camera.aperture_radius: a thin lens is not translated")
    out = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 64, "rr_depth": 8},
        "sensor": {
            "type": "perspective", "fov_axis": "y", "fov": float(cam.get("verticalFovDegrees", 40)),
            "to_world": mi.ScalarTransform4f().look_at(origin=vec(cam["position"], "x", "y", "z"),
                                                        target=vec(cam["lookAt"], "x", "y", "z"),
                                                        up=vec(cam["up"], "x", "y", "z")),
            "sampler": {"type": "independent", "sample_count": spp, "seed": seed},
            "film": {"type": "hdrfilm", "width": int(film["width"]), "height": int(film["height"]),
                     "pixel_format": "rgb", "rfilter": {"type": "box"}},
        },
    }
    bsdfs = {m["name"]: bsdf_of(scene, root, m) for m in scene.get("materials", [])}
    plys, material_of = {}, {}
    for mesh in scene.get("meshes", []):
        for i, part in enumerate(mesh["parts"]):
            ply = work_dir / f"{len(plys)}.ply"
            write_ply(ply, *read_farm_mesh(root / part["path"]))
            plys[(mesh["name"], i)] = (ply, part["material"])
    materials = {m["name"]: m for m in scene.get("materials", [])}
    for n, shape in enumerate(scene.get("shapes", [])):
        geometry = geometry_of(mi, shape, work_dir / f"shape{n}.ply")
        if geometry is not None:
            material = materials[shape["material"]]
            geometry["bsdf"] = copy.deepcopy(bsdfs[material["name"]])
            emitter = emitter_of(material)
            if emitter:
                geometry["emitter"] = emitter
            out[f"shape{n}"] = geometry
            material_of[f"shape{n}"] = material["name"]
            continue
        if "instance" not in shape:
            raise Unsupported(f"shapes[{n}]: only spheres, quads, triangles and instances of Scene.meshes are translated")
        inst = shape["instance"]
        to_world = matrix_of(mi, inst.get("transform"))
        for (mesh_name, i), (ply, material) in plys.items():
            if mesh_name == inst["mesh"]:
                out[f"shape{n}_{i}"] = {"type": "ply", "filename": str(ply), "to_world": to_world,
                                            # a BSDF of its own: Mitsuba merges the meshes that share one
                                            "bsdf": copy.deepcopy(bsdfs[material])}
                material_of[f"shape{n}_{i}"] = material
    env = scene.get("environment")
    if env:
        if env.get("hiddenFromCamera"):
            raise Unsupported("environment.hidden_from_camera is not translated")
        if "map" in env:
            tex = next(t for t in scene.get("textures", []) if t["name"] == env["map"]["texture"])
            emitter = {"type": "envmap", "filename": str(root / tex["path"]),
                       "to_world": mi.ScalarTransform4f().rotate([0, 1, 0], 180 + float(env.get("rotationDegrees", 0)))}
            if "radiance" in env:
                c = vec(env["radiance"], "r", "g", "b")
                if len(set(c)) != 1:
                    raise Unsupported("environment.radiance tinting a map is not translated")
                emitter["scale"] = c[0]
        else:
            emitter = {"type": "constant", "radiance": rgb(env["radiance"])}
        out["environment"] = emitter
    for n, light in enumerate(scene.get("lights", [])):
        if "sun" in light:
            sun = light["sun"]
            if sun.get("angularDiameterDegrees", 0):
                raise Unsupported(f"lights[{n}].sun.angular_diameter_degrees: a sun disc is not translated")
            out[f"light{n}"] = {"type": "directional", "direction": vec(sun["direction"], "x", "y", "z"), "irradiance": rgb(sun["irradiance"])}
        elif "point" in light:
            pt = light["point"]
            out[f"light{n}"] = {"type": "point", "position": vec(pt["position"], "x", "y", "z"), "intensity": rgb(pt["intensity"])}
        else:
            raise Unsupported(f"lights[{n}]: only sun and point lights are translated")
    add_media(out, scene, root)
    return out, material_of
