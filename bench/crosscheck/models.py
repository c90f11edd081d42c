"""The two models of the Mitsuba cross-check (issue 13, acceptance 4), written as glTF 2.0
files (.gltf + .bin + PNG images) and a Radiance HDR sky, by this code and nothing else:

  textured   a checkered floor and a striped box and ball, glTF metallic-roughness
             materials with base colour textures (metallic 0), lit by the sky map alone
  metals     a grey floor, two metal balls (gold roughness 0.25, copper 0.5) and a rough
             blue dielectric one, under the same sky and a glTF directional light (a sun)

Every number is fixed, so the files are the same at every run."""

import base64
import json
import math
import struct
import zlib
from pathlib import Path

import numpy as np


def write_png(path, rgb):
    """8-bit sRGB-coded RGB PNG of an HxWx3 uint8 array."""
    h, w, _ = rgb.shape
    raw = b"".join(b"\x00" + rgb[y].tobytes() for y in range(h))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    Path(path).write_bytes(png)


def write_hdr(path, rgb):
    """Radiance HDR (RGBE, flat scanlines) of an HxWx3 float array, top row first."""
    h, w, _ = rgb.shape
    m = rgb.max(axis=2)
    e = np.where(m > 1e-32, np.floor(np.log2(np.maximum(m, 1e-32))) + 1, -128)
    scale = np.where(m > 1e-32, 256.0 / np.exp2(e), 0)
    out = np.zeros((h, w, 4), np.uint8)
    out[..., :3] = np.clip(rgb * scale[..., None], 0, 255).astype(np.uint8)
    out[..., 3] = np.where(m > 1e-32, e + 128, 0).astype(np.uint8)
    header = f"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {h} +X {w}\n".encode()
    Path(path).write_bytes(header + out.tobytes())


def sky(width=256, height=128):
    """A blue sky brightening to the horizon, a warm disc of about 12 degrees (bright, but
    wide enough that both renderers find it without fireflies), a grey-brown ground."""
    v = (np.arange(height) + 0.5) / height
    u = (np.arange(width) + 0.5) / width
    theta = v[:, None] * math.pi  # 0 up
    phi = (u[None, :] - 0.5) * 2 * math.pi  # farm: u = 0.5 looks along -Z, +X at 0.75
    d = np.stack([np.sin(theta) * np.sin(phi) * np.ones_like(phi),
                  np.cos(theta) * np.ones_like(phi),
                  -np.sin(theta) * np.cos(phi)], axis=-1)
    up = d[..., 1]
    zenith, horizon, ground = np.array([0.25, 0.45, 0.9]), np.array([0.9, 0.95, 1.0]), np.array([0.3, 0.25, 0.2])
    t = np.clip(up, 0, 1)[..., None] ** 0.5
    img = np.where(up[..., None] > 0, horizon * (1 - t) + zenith * t, ground)
    sun = np.array([0.45, 0.6, -0.66])
    sun /= np.linalg.norm(sun)
    img = img + np.where((d @ sun > math.cos(math.radians(6)))[..., None], np.array([12.0, 10.0, 7.0]), 0)
    return img.astype(np.float32)


def checker(n, checks, a, b):
    y, x = np.mgrid[0:n, 0:n]
    odd = ((x * checks // n) + (y * checks // n)) % 2 == 1
    img = np.where(odd[..., None], np.array(a, np.uint8), np.array(b, np.uint8)).astype(np.uint8)
    img[: n // checks, : n // checks] = (200, 30, 30)  # a red corner: which way up the image is
    return img


def stripes(n, count, a, b):
    y, x = np.mgrid[0:n, 0:n]
    band = (x * count // n) % 2 == 1
    img = np.where(band[..., None], np.array(a, np.uint8), np.array(b, np.uint8)).astype(np.uint8)
    img[: n // 4] = (40, 140, 60)  # a green top: which way up the image is
    return img


def quad(size):
    s = size / 2
    pos = [(-s, 0, s), (s, 0, s), (s, 0, -s), (-s, 0, -s)]
    nrm = [(0, 1, 0)] * 4
    uv = [(0, 0), (1, 0), (1, 1), (0, 1)]
    return pos, nrm, uv, [0, 1, 2, 0, 2, 3]


def box(half):
    pos, nrm, uv, idx = [], [], [], []
    for axis in range(3):
        for sign in (1, -1):
            n = [0, 0, 0]
            n[axis] = sign
            a, b = [(axis + 1) % 3, (axis + 2) % 3][:: sign]
            base = len(pos)
            for cu, cv in ((0, 0), (1, 0), (1, 1), (0, 1)):
                p = [0.0, 0.0, 0.0]
                p[axis] = sign * half
                p[a] = (2 * cu - 1) * half
                p[b] = (2 * cv - 1) * half
                pos.append(tuple(p))
                nrm.append(tuple(n))
                uv.append((cu, 1 - cv))
            idx += [base, base + 1, base + 2, base, base + 2, base + 3]
    return pos, nrm, uv, idx


def ball(radius, rings=48, segments=96):
    pos, nrm, uv, idx = [], [], [], []
    for i in range(rings + 1):
        th = math.pi * i / rings
        for j in range(segments + 1):
            ph = 2 * math.pi * j / segments
            n = (math.sin(th) * math.cos(ph), math.cos(th), -math.sin(th) * math.sin(ph))
            pos.append(tuple(radius * c for c in n))
            nrm.append(n)
            uv.append((j / segments, i / rings))
    for i in range(rings):
        for j in range(segments):
            a, b = i * (segments + 1) + j, (i + 1) * (segments + 1) + j
            idx += [a, b, a + 1, a + 1, b, b + 1]
    return pos, nrm, uv, idx


class Gltf:
    """A glTF document with one external buffer."""

    def __init__(self):
        self.doc = {"asset": {"version": "2.0", "generator": "photonfarm bench/crosscheck"},
                    "scene": 0, "scenes": [{"nodes": []}], "nodes": [], "meshes": [], "materials": [],
                    "accessors": [], "bufferViews": [], "buffers": [], "images": [], "textures": [],
                    "samplers": [{"wrapS": 10497, "wrapT": 10497}]}
        self.bin = bytearray()

    def _view(self, data, target):
        while len(self.bin) % 4:
            self.bin.append(0)
        self.doc["bufferViews"].append({"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data), "target": target})
        self.bin += data
        return len(self.doc["bufferViews"]) - 1

    def _accessor(self, values, kind):
        arr = np.asarray(values, np.float32)
        acc = {"bufferView": self._view(arr.tobytes(), 34962), "componentType": 5126, "count": len(arr), "type": kind}
        if kind == "VEC3":
            acc["min"], acc["max"] = arr.min(axis=0).tolist(), arr.max(axis=0).tolist()
        self.doc["accessors"].append(acc)
        return len(self.doc["accessors"]) - 1

    def texture(self, dir, name, rgb):
        write_png(Path(dir) / f"{name}.png", rgb)
        self.doc["images"].append({"uri": f"{name}.png"})
        self.doc["textures"].append({"source": len(self.doc["images"]) - 1, "sampler": 0})
        return len(self.doc["textures"]) - 1

    def material(self, name, color=(1, 1, 1), metallic=0.0, roughness=1.0, texture=None):
        pbr = {"baseColorFactor": [*color, 1], "metallicFactor": metallic, "roughnessFactor": roughness}
        if texture is not None:
            pbr["baseColorTexture"] = {"index": texture}
        self.doc["materials"].append({"name": name, "pbrMetallicRoughness": pbr})
        return len(self.doc["materials"]) - 1

    def mesh(self, name, geometry, material):
        pos, nrm, uv, idx = geometry
        ind = np.asarray(idx, np.uint32)
        self.doc["accessors"].append({"bufferView": self._view(ind.tobytes(), 34963), "componentType": 5125,
                                      "count": len(ind), "type": "SCALAR"})
        indices = len(self.doc["accessors"]) - 1
        prim = {"attributes": {"POSITION": self._accessor(pos, "VEC3"), "NORMAL": self._accessor(nrm, "VEC3"),
                               "TEXCOORD_0": self._accessor(uv, "VEC2")},
                "indices": indices, "material": material}
        self.doc["meshes"].append({"name": name, "primitives": [prim]})
        return len(self.doc["meshes"]) - 1

    def node(self, **node):
        self.doc["nodes"].append(node)
        self.doc["scenes"][0]["nodes"].append(len(self.doc["nodes"]) - 1)

    def camera(self, eye, target, yfov_degrees):
        """A perspective camera at eye looking at target, +Y up (its rotation as a quaternion)."""
        f = np.subtract(target, eye, dtype=float)
        f /= np.linalg.norm(f)
        r = np.cross(f, (0, 1, 0))
        r /= np.linalg.norm(r)
        u = np.cross(r, f)
        m = np.column_stack([r, u, -f])  # the camera looks along its -Z
        w = math.sqrt(max(0.0, 1 + m[0, 0] + m[1, 1] + m[2, 2])) / 2
        q = [(m[2, 1] - m[1, 2]) / (4 * w), (m[0, 2] - m[2, 0]) / (4 * w), (m[1, 0] - m[0, 1]) / (4 * w), w]
        self.doc["cameras"] = [{"type": "perspective",
                                "perspective": {"yfov": math.radians(yfov_degrees), "aspectRatio": 1.0, "znear": 0.01}}]
        self.node(camera=0, translation=list(map(float, eye)), rotation=q)

    def save(self, dir, name):
        (Path(dir) / f"{name}.bin").write_bytes(bytes(self.bin))
        self.doc["buffers"] = [{"uri": f"{name}.bin", "byteLength": len(self.bin)}]
        path = Path(dir) / f"{name}.gltf"
        path.write_text(json.dumps(self.doc, indent=1))
        return path


def textured(dir):
    g = Gltf()
    floor = g.material("floor", roughness=0.6, texture=g.texture(dir, "floor", checker(128, 8, (230, 220, 200), (60, 70, 90))))
    striped = g.material("stripes", roughness=0.5, texture=g.texture(dir, "stripes", stripes(64, 8, (240, 200, 60), (60, 40, 150))))
    g.node(mesh=g.mesh("floor", quad(8), floor))
    g.node(mesh=g.mesh("box", box(0.5), striped), translation=[-0.8, 0.5, 0.2], rotation=[0, math.sin(0.3), 0, math.cos(0.3)])
    g.node(mesh=g.mesh("ball", ball(0.55), striped), translation=[0.8, 0.55, -0.2])
    g.camera((0.0, 1.5, 4.6), (0.0, 0.5, 0.0), 40)
    return g.save(dir, "textured")


def metals(dir):
    g = Gltf()
    g.node(mesh=g.mesh("floor", quad(10), g.material("floor", (0.6, 0.6, 0.6), roughness=0.9)))
    for x, name, color, metallic, roughness in ((-1.25, "gold", (1.0, 0.78, 0.34), 1.0, 0.25),
                                                (0.0, "copper", (0.95, 0.64, 0.54), 1.0, 0.5),
                                                (1.25, "blue", (0.1, 0.2, 0.7), 0.0, 0.4)):
        g.node(mesh=g.mesh(name, ball(0.55), g.material(name, color, metallic, roughness)), translation=[x, 0.55, 0.0])
    g.doc["extensionsUsed"] = ["KHR_lights_punctual"]
    g.doc["extensions"] = {"KHR_lights_punctual": {"lights": [{"type": "directional", "color": [1.0, 0.95, 0.85], "intensity": 1366.0}]}}
    # Light travels along the node's -Z: rotate it so that it falls from above, behind the camera's left.
    d = np.array([0.5, -0.8, -0.45])
    d /= np.linalg.norm(d)
    axis = np.cross((0, 0, -1), d)
    angle = math.acos(np.dot((0, 0, -1), d))
    axis /= np.linalg.norm(axis)
    g.node(extensions={"KHR_lights_punctual": {"light": 0}}, rotation=[*(axis * math.sin(angle / 2)).tolist(), math.cos(angle / 2)])
    g.camera((0.0, 1.7, 5.6), (0.0, 0.45, 0.0), 35)
    return g.save(dir, "metals")
