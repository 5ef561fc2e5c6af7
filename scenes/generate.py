#!/usr/bin/python3
"""Generates the glTF 2.0 scenes that Partita ships.

    python3 scenes/generate.py              # (re)write every scene next to this script
    python3 scenes/generate.py pool cornell # only these scenes
    python3 scenes/generate.py --out DIR    # write under DIR instead
    python3 scenes/generate.py --check      # verify the files on disk (see check_scene)

Each scene is written as <name>/<name>.gltf with one external buffer <name>/<name>.bin (textures
are PNGs stored in that buffer). Standard library only; the output is byte-for-byte deterministic
(sorted JSON keys, floats rounded before they are written, PNGs written as stored deflate blocks so
that no zlib version can change a byte).

Conventions: metres, +Y up, right-handed. All geometry is baked in world space (mesh nodes have no
transform); the camera node "main" carries translation + rotation and looks down its local -Z.
Area lights are one-sided emissive meshes (emissiveFactor (1,1,1) scaled by
KHR_materials_emissive_strength) whose normal points into the lit room. Closed objects (boxes,
spheres, glass slabs) have outward normals and counter-clockwise winding seen from outside; room
shells face inward.
"""

import json
import math
import os
import struct
import sys
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE_NAMES = ("cornell", "cornell-glass", "door-ajar", "bathroom", "pool")
ASPECT = 4.0 / 3.0  # the default 320x240 image

# --------------------------------------------------------------------------------------------
# small vector helpers (tuples of floats)


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def mul(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def length(a):
    return math.sqrt(dot(a, a))


def normalize(a):
    n = length(a)
    return (a[0] / n, a[1] / n, a[2] / n)


def rot_y(v, angle):
    """Rotates v about +Y by angle (radians, counter-clockwise seen from above)."""
    c, s = math.cos(angle), math.sin(angle)
    return (c * v[0] + s * v[2], v[1], -s * v[0] + c * v[2])


def clean(x, digits=6):
    """A float rounded for JSON, with -0.0 folded into 0.0."""
    r = round(float(x), digits)
    return 0.0 if r == 0 else r


def f32(x):
    """x rounded to the float32 the buffer will hold."""
    return struct.unpack("<f", struct.pack("<f", x))[0]


# --------------------------------------------------------------------------------------------
# geometry


class Mesh:
    """One glTF mesh with one indexed-triangle primitive and one material."""

    def __init__(self, name, material, uv_scale=None):
        self.name = name
        self.material = material
        self.uv_scale = uv_scale  # metres per texture repeat; None = no TEXCOORD_0
        self.positions, self.normals, self.uvs, self.indices = [], [], [], []

    def vertex(self, p, n, uv=None):
        self.positions.append(tuple(p))
        self.normals.append(normalize(n))
        if self.uv_scale is not None:
            if uv is None:
                uv = planar_uv(p, n, self.uv_scale)
            self.uvs.append(tuple(uv))
        return len(self.positions) - 1

    def triangle(self, a, b, c):
        self.indices.extend((a, b, c))

    def triangle_count(self):
        return len(self.indices) // 3


def planar_uv(p, n, scale):
    """World-space planar mapping along the dominant axis of n (tiles line up across walls)."""
    ax, ay, az = abs(n[0]), abs(n[1]), abs(n[2])
    if ay >= ax and ay >= az:
        u, v = p[0], p[2]
    elif ax >= az:
        u, v = p[2], -p[1]
    else:
        u, v = p[0], -p[1]
    return (u / scale, v / scale)


def add_polygon(mesh, pts, facing):
    """A planar convex polygon (flat normal) whose front side faces the direction `facing`."""
    gn = cross(sub(pts[1], pts[0]), sub(pts[2], pts[0]))
    if dot(gn, facing) < 0:
        pts = list(reversed(pts))
        gn = mul(gn, -1.0)
    n = normalize(gn)
    idx = [mesh.vertex(p, n) for p in pts]
    for i in range(1, len(idx) - 1):
        mesh.triangle(idx[0], idx[i], idx[i + 1])


def add_rect(mesh, lo, hi, normal):
    """An axis-aligned rectangle spanning lo..hi (one coordinate equal) facing `normal`."""
    axis = [i for i in range(3) if lo[i] == hi[i]]
    assert len(axis) == 1, (lo, hi)
    a = axis[0]
    u, v = [i for i in range(3) if i != a]

    def pt(su, sv):
        p = [0.0, 0.0, 0.0]
        p[a] = lo[a]
        p[u] = hi[u] if su else lo[u]
        p[v] = hi[v] if sv else lo[v]
        return tuple(p)

    add_polygon(mesh, [pt(0, 0), pt(1, 0), pt(1, 1), pt(0, 1)], normal)


def add_oriented_box(mesh, origin, ea, eb, ec, skip=()):
    """A closed box spanned by origin + {0,1}ea + {0,1}eb + {0,1}ec, outward normals.
    skip: faces to leave out, named by ('-a', '+a', '-b', '+b', '-c', '+c')."""
    centre = add(origin, mul(add(add(ea, eb), ec), 0.5))
    edges = {"a": ea, "b": eb, "c": ec}
    for axis in ("a", "b", "c"):
        e = edges[axis]
        others = [edges[k] for k in ("a", "b", "c") if k != axis]
        for side, sign in (("-", 0.0), ("+", 1.0)):
            if side + axis in skip:
                continue
            o = add(origin, mul(e, sign))
            pts = [o, add(o, others[0]), add(add(o, others[0]), others[1]), add(o, others[1])]
            face_centre = add(o, mul(add(others[0], others[1]), 0.5))
            add_polygon(mesh, pts, sub(face_centre, centre))


def add_box(mesh, centre, size, yaw=0.0, skip=()):
    """An axis-aligned (then rotated about Y by yaw) box with outward normals."""
    ea = rot_y((size[0], 0.0, 0.0), yaw)
    eb = (0.0, size[1], 0.0)
    ec = rot_y((0.0, 0.0, size[2]), yaw)
    origin = sub(centre, mul(add(add(ea, eb), ec), 0.5))
    add_oriented_box(mesh, origin, ea, eb, ec, skip)


def add_room(meshes, lo, hi):
    """An inward-facing box shell. meshes maps face name (floor, ceiling, left (-x), right (+x),
    back (-z), front (+z)) to the Mesh it goes into; faces mapped to None are left out."""
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    faces = {
        "floor": ((x0, y0, z0), (x1, y0, z1), (0, 1, 0)),
        "ceiling": ((x0, y1, z0), (x1, y1, z1), (0, -1, 0)),
        "left": ((x0, y0, z0), (x0, y1, z1), (1, 0, 0)),
        "right": ((x1, y0, z0), (x1, y1, z1), (-1, 0, 0)),
        "back": ((x0, y0, z0), (x1, y1, z0), (0, 0, 1)),
        "front": ((x0, y0, z1), (x1, y1, z1), (0, 0, -1)),
    }
    for key in ("floor", "ceiling", "left", "right", "back", "front"):
        m = meshes.get(key)
        if m is not None:
            a, b, n = faces[key]
            add_rect(m, a, b, n)


def add_sphere(mesh, centre, radius, segments=32, rings=20):
    """A UV sphere with smooth (analytic) normals; the pole rows are triangles, not quads."""
    grid = []
    for i in range(rings + 1):
        theta = math.pi * i / rings
        row = []
        for j in range(segments + 1):
            phi = 2.0 * math.pi * (j % segments) / segments
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi))
            if i == 0:
                n = (0.0, 1.0, 0.0)
            elif i == rings:
                n = (0.0, -1.0, 0.0)
            p = add(centre, mul(n, radius))
            row.append(mesh.vertex(p, n, (j / segments, i / rings)))
        grid.append(row)
    for i in range(rings):
        for j in range(segments):
            a, b = grid[i][j], grid[i + 1][j]
            c, d = grid[i + 1][j + 1], grid[i][j + 1]
            # counter-clockwise seen from outside: phi grows clockwise seen from +Y here
            if i != 0:
                mesh.triangle(a, b, d)
            if i != rings - 1:
                mesh.triangle(d, b, c)


def add_heightfield(mesh, x0, x1, z0, z1, cells_x, cells_z, height, gradient):
    """A grid y = height(x, z) with smooth normals from the analytic gradient, facing +Y."""
    idx = []
    for i in range(cells_z + 1):
        z = z0 + (z1 - z0) * i / cells_z
        row = []
        for j in range(cells_x + 1):
            x = x0 + (x1 - x0) * j / cells_x
            gx, gz = gradient(x, z)
            row.append(mesh.vertex((x, height(x, z), z), (-gx, 1.0, -gz)))
        idx.append(row)
    for i in range(cells_z):
        for j in range(cells_x):
            a, b = idx[i][j], idx[i][j + 1]
            c, d = idx[i + 1][j + 1], idx[i + 1][j]
            # z grows with i: (a, d, c) is counter-clockwise seen from +Y
            if (i + j) % 2 == 0:
                mesh.triangle(a, d, c)
                mesh.triangle(a, c, b)
            else:
                mesh.triangle(a, d, b)
                mesh.triangle(b, d, c)


# --------------------------------------------------------------------------------------------
# PNG (stored deflate blocks: deterministic regardless of the zlib build)


def png_rgb(width, height, pixel):
    raw = bytearray()
    for y in range(height):
        raw.append(0)  # filter: none
        for x in range(width):
            raw.extend(pixel(x, y))
    raw = bytes(raw)
    stream = bytearray(b"\x78\x01")
    pos = 0
    while True:
        block = raw[pos:pos + 65535]
        pos += len(block)
        final = 1 if pos >= len(raw) else 0
        stream += struct.pack("<BHH", final, len(block), len(block) ^ 0xFFFF) + block
        if final:
            break
    stream += struct.pack(">I", zlib.adler32(raw) & 0xFFFFFFFF)

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))

    return (b"\x89PNG\r\n\x1a\n"
            + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", bytes(stream)) + chunk(b"IEND", b""))


def tile_texture(light, dark, grout, size=64, tile=8):
    """A checker of size/tile tiles per side with one-pixel grout lines (sRGB bytes)."""

    def pixel(x, y):
        if x % tile == 0 or y % tile == 0:
            return grout
        return light if ((x // tile) + (y // tile)) % 2 == 0 else dark

    return png_rgb(size, size, pixel)


# --------------------------------------------------------------------------------------------
# scene description and glTF writer


class Scene:
    def __init__(self, name):
        self.name = name
        self.materials = []  # (name, dict)
        self.material_index = {}
        self.images = []  # PNG bytes
        self.meshes = []
        self.camera = None
        self.extensions = set()
        # expectations that --check verifies by casting rays from the camera
        self.must_see = []  # mesh names that must cover part of the image
        self.max_light_fraction = 0.02  # share of the image that may show an emitter directly
        self.open_glass = []  # transmissive meshes that are deliberately not closed
        self.point_lights = []  # (name, position, intensity): KHR_lights_punctual point lights

    def texture(self, png):
        self.images.append(png)
        return len(self.images) - 1

    def material(self, name, base=(0.8, 0.8, 0.8), metallic=0.0, roughness=1.0, texture=None,
                 emission=0.0, transmission=0.0, ior=None, double_sided=False):
        pbr = {"baseColorFactor": [clean(c) for c in base] + [1.0],
               "metallicFactor": clean(metallic), "roughnessFactor": clean(roughness)}
        if texture is not None:
            pbr["baseColorTexture"] = {"index": texture}
        m = {"name": name, "pbrMetallicRoughness": pbr}
        ext = {}
        if emission > 0:
            m["emissiveFactor"] = [1.0, 1.0, 1.0]
            if emission != 1.0:
                ext["KHR_materials_emissive_strength"] = {"emissiveStrength": clean(emission)}
        if transmission > 0:
            ext["KHR_materials_transmission"] = {"transmissionFactor": clean(transmission)}
        if ior is not None:
            ext["KHR_materials_ior"] = {"ior": clean(ior)}
        if ext:
            m["extensions"] = ext
            self.extensions.update(ext)
        if double_sided:
            m["doubleSided"] = True
        self.material_index[name] = len(self.materials)
        self.materials.append(m)
        return name

    def mesh(self, name, material, uv_scale=None):
        m = Mesh(name, material, uv_scale)
        self.meshes.append(m)
        return m

    def look_at(self, eye, target, yfov_degrees, up=(0.0, 1.0, 0.0)):
        self.camera = (tuple(eye), tuple(target), yfov_degrees, up)

    # ----------------------------------------------------------------------------------------

    def to_gltf(self):
        """Returns (gltf bytes, bin bytes)."""
        blob = bytearray()
        views, accessors = [], []

        def put(data, target=None):
            while len(blob) % 4:
                blob.append(0)
            view = {"buffer": 0, "byteOffset": len(blob), "byteLength": len(data)}
            if target is not None:
                view["target"] = target
            blob.extend(data)
            views.append(view)
            return len(views) - 1

        def accessor(values, kind, with_bounds=False):
            n = {"VEC2": 2, "VEC3": 3}[kind]
            flat = [f32(c) for v in values for c in v]
            data = struct.pack("<%df" % len(flat), *flat)
            acc = {"bufferView": put(data, 34962), "componentType": 5126,
                   "count": len(values), "type": kind}
            if with_bounds:
                acc["min"] = [min(flat[i::n]) for i in range(n)]
                acc["max"] = [max(flat[i::n]) for i in range(n)]
            accessors.append(acc)
            return len(accessors) - 1

        gmeshes, nodes = [], []
        eye, target, yfov, up = self.camera
        nodes.append({"name": "main", "camera": 0,
                      "translation": [clean(c) for c in eye],
                      "rotation": [clean(c, 7) for c in look_rotation(eye, target, up)]})
        for m in self.meshes:
            assert m.indices and max(m.indices) < len(m.positions), m.name
            attrs = {"POSITION": accessor(m.positions, "VEC3", True),
                     "NORMAL": accessor(m.normals, "VEC3")}
            if m.uvs:
                attrs["TEXCOORD_0"] = accessor(m.uvs, "VEC2")
            if len(m.positions) < 65535:
                data, ctype = struct.pack("<%dH" % len(m.indices), *m.indices), 5123
            else:
                data, ctype = struct.pack("<%dI" % len(m.indices), *m.indices), 5125
            accessors.append({"bufferView": put(data, 34963), "componentType": ctype,
                              "count": len(m.indices), "type": "SCALAR"})
            prim = {"attributes": attrs, "indices": len(accessors) - 1,
                    "material": self.material_index[m.material], "mode": 4}
            gmeshes.append({"name": m.name, "primitives": [prim]})
            nodes.append({"name": m.name, "mesh": len(gmeshes) - 1})

        images = []
        for png in self.images:
            images.append({"bufferView": put(png), "mimeType": "image/png"})
        while len(blob) % 4:
            blob.append(0)

        doc = {
            "asset": {"version": "2.0", "generator": "Partita scenes/generate.py"},
            "scene": 0,
            "scenes": [{"name": self.name, "nodes": list(range(len(nodes)))}],
            "nodes": nodes,
            "cameras": [{"name": "main", "type": "perspective",
                         "perspective": {"yfov": clean(math.radians(yfov)),
                                         "aspectRatio": clean(ASPECT),
                                         "znear": 0.01}}],
            "meshes": gmeshes,
            "materials": list(self.materials),
            "accessors": accessors,
            "bufferViews": views,
            "buffers": [{"uri": self.name + ".bin", "byteLength": len(blob)}],
        }
        if self.point_lights:
            # Each light hangs on a node of its own, placed by translation.
            doc["extensions"] = {"KHR_lights_punctual": {"lights": [
                {"name": name, "type": "point", "color": [1.0, 1.0, 1.0],
                 "intensity": clean(intensity)} for name, _, intensity in self.point_lights]}}
            for i, (name, pos, _) in enumerate(self.point_lights):
                nodes.append({"name": name, "translation": [clean(c) for c in pos],
                              "extensions": {"KHR_lights_punctual": {"light": i}}})
            doc["scenes"][0]["nodes"] = list(range(len(nodes)))
            self.extensions.add("KHR_lights_punctual")
        if images:
            doc["images"] = images
            doc["samplers"] = [{"magFilter": 9728, "minFilter": 9987,
                                "wrapS": 10497, "wrapT": 10497}]
            doc["textures"] = [{"sampler": 0, "source": i} for i in range(len(images))]
        if self.extensions:
            doc["extensionsUsed"] = sorted(self.extensions)
        text = json.dumps(doc, indent=1, sort_keys=True, ensure_ascii=True) + "\n"
        return text.encode("ascii"), bytes(blob)

    def triangle_count(self):
        return sum(m.triangle_count() for m in self.meshes)


def look_rotation(eye, target, up):
    """Quaternion (x, y, z, w) turning the camera's -Z towards target with +Y near up."""
    f = normalize(sub(target, eye))
    z = mul(f, -1.0)
    x = normalize(cross(up, z))
    y = cross(z, x)
    m00, m01, m02 = x[0], y[0], z[0]
    m10, m11, m12 = x[1], y[1], z[1]
    m20, m21, m22 = x[2], y[2], z[2]
    tr = m00 + m11 + m22
    if tr > 0:
        s = math.sqrt(tr + 1.0) * 2
        q = ((m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s, 0.25 * s)
    elif m00 > m11 and m00 > m22:
        s = math.sqrt(1.0 + m00 - m11 - m22) * 2
        q = (0.25 * s, (m01 + m10) / s, (m02 + m20) / s, (m21 - m12) / s)
    elif m11 > m22:
        s = math.sqrt(1.0 + m11 - m00 - m22) * 2
        q = ((m01 + m10) / s, 0.25 * s, (m12 + m21) / s, (m02 - m20) / s)
    else:
        s = math.sqrt(1.0 + m22 - m00 - m11) * 2
        q = ((m02 + m20) / s, (m12 + m21) / s, 0.25 * s, (m10 - m01) / s)
    if q[3] < 0:
        q = tuple(-c for c in q)
    return normalize4(q)


def normalize4(q):
    n = math.sqrt(sum(c * c for c in q))
    return tuple(c / n for c in q)


# --------------------------------------------------------------------------------------------
# materials shared by several scenes

WHITE = (0.73, 0.71, 0.68)  # the Cornell box's measured reflectances, as linear RGB
RED = (0.63, 0.065, 0.05)
GREEN = (0.14, 0.45, 0.091)


def glass(scene, name="glass", ior=1.5):
    return scene.material(name, base=(1.0, 1.0, 1.0), roughness=0.0, transmission=1.0, ior=ior)


def mirror(scene, name="mirror"):
    return scene.material(name, base=(0.95, 0.95, 0.95), metallic=1.0, roughness=0.0)


def light(scene, strength, name="light"):
    # black base colour: the emitter is a pure source and reflects nothing
    return scene.material(name, base=(0.0, 0.0, 0.0), emission=strength)


# --------------------------------------------------------------------------------------------
# the Cornell box (data from the Cornell program of computer graphics, millimetres), turned
# 180 degrees about Y so that the camera looks down -Z, scaled to a 2 m box, closed at the front

CB_SCALE = 2.0 / 556.0


def cb(x, y, z):
    return ((278.0 - x) * CB_SCALE, y * CB_SCALE, (279.6 - z) * CB_SCALE)


CB_SHORT = [  # five quads each (the blocks stand on the floor)
    [(130, 165, 65), (82, 165, 225), (240, 165, 272), (290, 165, 114)],
    [(290, 0, 114), (290, 165, 114), (240, 165, 272), (240, 0, 272)],
    [(130, 0, 65), (130, 165, 65), (290, 165, 114), (290, 0, 114)],
    [(82, 0, 225), (82, 165, 225), (130, 165, 65), (130, 0, 65)],
    [(240, 0, 272), (240, 165, 272), (82, 165, 225), (82, 0, 225)],
]
CB_TALL = [
    [(423, 330, 247), (265, 330, 296), (314, 330, 456), (472, 330, 406)],
    [(423, 0, 247), (423, 330, 247), (472, 330, 406), (472, 0, 406)],
    [(472, 0, 406), (472, 330, 406), (314, 330, 456), (314, 0, 456)],
    [(314, 0, 456), (314, 330, 456), (265, 330, 296), (265, 0, 296)],
    [(265, 0, 296), (265, 330, 296), (423, 330, 247), (423, 0, 247)],
]


def cornell_shell(s, strength):
    return cornell_walls(s, strength)


def cornell_walls(s, strength):
    """The box: white floor/ceiling/back, red left, green right; the floor, ceiling and side walls
    run on past the open front to a white wall behind the camera so that no light escapes."""
    white = s.material("white", base=WHITE)
    red = s.material("red", base=RED)
    green = s.material("green", base=GREEN)
    lo = cb(556.0, 0.0, 559.2)
    hi = cb(0.0, 548.8, -1200.0)
    add_room({"floor": s.mesh("floor", white), "ceiling": s.mesh("ceiling", white),
              "back": s.mesh("back_wall", white), "front": s.mesh("front_wall", white),
              "left": s.mesh("left_wall", red), "right": s.mesh("right_wall", green)},
             (lo[0], lo[1], lo[2]), (hi[0], hi[1], hi[2]))
    if strength is not None:
        lamp = s.mesh("light", light(s, strength))
        y = 548.8 - 0.5  # half a millimetre below the ceiling
        add_polygon(lamp, [cb(343, y, 227), cb(343, y, 332), cb(213, y, 332), cb(213, y, 227)],
                    (0, -1, 0))
    s.look_at(cb(278, 273, -800), cb(278, 273, 0), 39.3)
    return white


def scene_cornell():
    s = Scene("cornell")
    white = cornell_shell(s, 17.0)
    for name, quads in (("short_block", CB_SHORT), ("tall_block", CB_TALL)):
        m = s.mesh(name, white)
        pts = [cb(*p) for q in quads for p in q]
        centre = mul(add(min3(pts), max3(pts)), 0.5)
        for q in quads:
            q = [cb(*p) for p in q]
            add_polygon(m, q, sub(mul(add(q[0], q[2]), 0.5), centre))
    s.must_see = ["short_block", "tall_block", "left_wall", "right_wall", "light"]
    return s


def min3(pts):
    return tuple(min(p[i] for p in pts) for i in range(3))


def max3(pts):
    return tuple(max(p[i] for p in pts) for i in range(3))


def scene_cornell_glass():
    s = Scene("cornell-glass")
    cornell_shell(s, 17.0)
    r = 0.33  # resting 1 mm above the floor
    add_sphere(s.mesh("mirror_sphere", mirror(s)), (-0.42, r + 0.001, -0.38), r)
    add_sphere(s.mesh("glass_sphere", glass(s)), (0.42, r + 0.001, 0.28), r)
    s.must_see = ["mirror_sphere", "glass_sphere", "light"]
    return s


def scene_cornell_point():
    """The Cornell box lit by one point light above a glass sphere: the sphere focuses it into an
    LSSDE caustic on the floor, which a path tracer cannot sample (a delta light behind a
    specular chain) and light tracing / BDPT can."""
    s = Scene("cornell-point")
    cornell_walls(s, None)
    r = 0.33
    add_sphere(s.mesh("glass_sphere", glass(s)), (0.0, r + 0.001, -0.05), r)
    s.point_lights.append(("point_light", (0.0, 1.45, -0.05), 1.5))
    s.must_see = ["glass_sphere", "floor", "back_wall"]
    return s


# --------------------------------------------------------------------------------------------
# door-ajar: two rooms joined by a door that stands a little open; the only light is in the
# far room, out of the camera's sight, so almost everything the camera sees is lit indirectly


def scene_door_ajar():
    s = Scene("door-ajar")
    wall = s.material("wall", base=(0.72, 0.70, 0.66))
    floor_m = s.material("floor", base=(0.45, 0.32, 0.20))
    ceiling_m = s.material("ceiling", base=(0.80, 0.80, 0.80))
    wood = s.material("wood", base=(0.35, 0.20, 0.10))
    door_m = s.material("door", base=(0.50, 0.60, 0.68))

    W, H = 2.5, 2.6          # half width, height
    zA, zB = 0.0, -7.1       # front of room A (behind the camera), back of room B
    wz0, wz1 = -4.1, -4.0    # the partition wall
    dx0, dx1, dh = 0.6, 1.5, 2.1  # the door opening

    add_room({"floor": s.mesh("floor", floor_m), "ceiling": s.mesh("ceiling", ceiling_m),
              "left": s.mesh("left_wall", wall), "right": s.mesh("right_wall", wall),
              "back": s.mesh("far_wall", wall), "front": s.mesh("near_wall", wall)},
             (-W, 0.0, zB), (W, H, zA))
    part = s.mesh("partition", wall)
    for z, n in ((wz1, (0, 0, 1)), (wz0, (0, 0, -1))):
        add_rect(part, (-W, 0.0, z), (dx0, H, z), n)
        add_rect(part, (dx1, 0.0, z), (W, H, z), n)
        add_rect(part, (dx0, dh, z), (dx1, H, z), n)
    add_rect(part, (dx0, 0.0, wz0), (dx0, dh, wz1), (1, 0, 0))   # jambs and head
    add_rect(part, (dx1, 0.0, wz0), (dx1, dh, wz1), (-1, 0, 0))
    add_rect(part, (dx0, dh, wz0), (dx1, dh, wz1), (0, -1, 0))

    # the door: hinged at the right jamb on room A's side and swung 20 degrees into room A. The
    # lamp's direct light through the opening lands on the back of the leaf and the jambs, so
    # room A gets no direct light at all; the camera sees a sliver of room B through the gap.
    angle = math.radians(20.0)
    hinge = (dx1 - 0.005, 0.005, wz1)
    leaf_w, leaf_h, leaf_t = dx1 - dx0 - 0.015, dh - 0.015, 0.04
    ea = rot_y((-leaf_w, 0.0, 0.0), angle)
    ec = rot_y((0.0, 0.0, leaf_t), angle)
    add_oriented_box(s.mesh("door", door_m), hinge, ea, (0.0, leaf_h, 0.0), ec)

    # the lamp: a ceiling panel in room B, left of the door, which the wall hides from the camera
    lamp = s.mesh("light", light(s, 500.0))
    add_rect(lamp, (-1.6, H - 0.002, -5.7), (-0.4, H - 0.002, -4.6), (0, -1, 0))

    # a table with a glass sphere and a glass box on it (glass lifted 1 mm off the top, so that no
    # glass face is coplanar with another surface)
    table = s.mesh("table", wood)
    tx, tz, ty = -0.7, -2.4, 0.75
    add_box(table, (tx, ty - 0.025, tz), (1.2, 0.05, 0.8))
    for sx in (-1, 1):
        for sz in (-1, 1):
            add_box(table, (tx + sx * 0.52, (ty - 0.05) / 2, tz + sz * 0.32),
                    (0.06, ty - 0.05, 0.06), skip=("-b", "+b"))
    g = glass(s)
    add_sphere(s.mesh("glass_sphere", g), (tx - 0.2, ty + 0.161, tz + 0.05), 0.16)
    add_box(s.mesh("glass_box", g), (tx + 0.3, ty + 0.101, tz - 0.1), (0.2, 0.2, 0.2),
            math.radians(30))

    s.look_at((-1.7, 1.55, -0.35), (0.35, 0.95, -4.0), 52.0)
    s.must_see = ["door", "table", "glass_sphere", "glass_box", "partition"]
    s.max_light_fraction = 0.0
    return s


# --------------------------------------------------------------------------------------------
# bathroom: a small bright ceiling spot, a glass shower panel, a wall mirror over a counter with
# glass objects on it, tiled walls and floor


def scene_bathroom():
    s = Scene("bathroom")
    tiles = s.texture(tile_texture((236, 236, 232), (212, 222, 230), (160, 164, 168)))
    tile_m = s.material("tiles", base=(1.0, 1.0, 1.0), texture=tiles)
    floor_m = s.material("floor_tiles", base=(0.55, 0.55, 0.55), texture=tiles)
    ceiling_m = s.material("ceiling", base=(0.85, 0.85, 0.85))
    counter_m = s.material("counter", base=(0.60, 0.45, 0.30))
    tray_m = s.material("shower_tray", base=(0.85, 0.85, 0.85))
    W, D, H = 1.5, 1.5, 2.5
    tile_repeat = 1.2  # 8 tiles of 15 cm per texture repeat
    add_room({"floor": s.mesh("floor", floor_m, tile_repeat),
              "ceiling": s.mesh("ceiling", ceiling_m),
              "left": s.mesh("left_wall", tile_m, tile_repeat),
              "right": s.mesh("right_wall", tile_m, tile_repeat),
              "back": s.mesh("back_wall", tile_m, tile_repeat),
              "front": s.mesh("front_wall", tile_m, tile_repeat)},
             (-W, 0.0, -D), (W, H, D))

    # counter along the back wall, mirror above it
    add_box(s.mesh("counter", counter_m), (-0.55, 0.425, -D + 0.275), (1.7, 0.85, 0.55),
            skip=("-b", "-c"))
    frame_m = s.material("frame", base=(0.10, 0.10, 0.10))
    add_box(s.mesh("mirror_frame", frame_m), (-0.55, 1.45, -D + 0.01), (1.56, 0.96, 0.02),
            skip=("-c",))
    add_rect(s.mesh("mirror", mirror(s)), (-1.3, 1.0, -D + 0.021), (0.2, 1.9, -D + 0.021),
             (0, 0, 1))

    # shower in the right back corner: a tray and a 1 cm glass panel closing its front
    g = glass(s)
    sx0, sz1 = 0.55, -0.35
    add_box(s.mesh("shower_tray", tray_m), ((sx0 + W) / 2, 0.03, (sz1 - D) / 2),
            (W - sx0, 0.06, sz1 + D), skip=("+a", "-b", "-c"))
    add_box(s.mesh("shower_panel", g), ((sx0 + 0.05 + W - 0.001) / 2, 0.061 + 0.95, sz1 - 0.006),
            (W - 0.001 - sx0 - 0.05, 1.9, 0.01))

    # glass objects on the counter, 1 mm above it
    top = 0.851
    add_sphere(s.mesh("glass_sphere", g), (-0.95, top + 0.12, -D + 0.3), 0.12)
    add_box(s.mesh("glass_box", g), (-0.45, top + 0.09, -D + 0.28), (0.18, 0.18, 0.18),
            math.radians(35))
    add_sphere(s.mesh("glass_ball", g), (-0.08, top + 0.06, -D + 0.36), 0.06, 24, 16)

    # the ceiling spot: 20 cm square, between counter and shower
    lamp = s.mesh("light", light(s, 180.0))
    add_rect(lamp, (-0.2, H - 0.002, -0.9), (0.0, H - 0.002, -0.7), (0, -1, 0))

    s.look_at((-1.15, 1.6, 1.3), (0.05, 0.95, -1.2), 60.0)
    s.must_see = ["mirror", "shower_panel", "glass_sphere", "glass_box", "counter"]
    return s


# --------------------------------------------------------------------------------------------
# pool: a small bright light above an indoor pool; the water is one wavy surface


POOL_WAVES = [  # (amplitude m, wavelength m, direction degrees, phase)
    (0.035, 1.20, 20.0, 0.3),
    (0.022, 0.80, 110.0, 1.7),
    (0.014, 0.60, 65.0, 4.1),
    (0.008, 0.45, 160.0, 2.6),
]


def wave_height(x, z, level):
    h = level
    for a, lam, deg, ph in POOL_WAVES:
        k = 2 * math.pi / lam
        dx, dz = math.cos(math.radians(deg)), math.sin(math.radians(deg))
        h += a * math.sin(k * (dx * x + dz * z) + ph)
    return h


def wave_gradient(x, z):
    gx = gz = 0.0
    for a, lam, deg, ph in POOL_WAVES:
        k = 2 * math.pi / lam
        dx, dz = math.cos(math.radians(deg)), math.sin(math.radians(deg))
        c = a * k * math.cos(k * (dx * x + dz * z) + ph)
        gx += c * dx
        gz += c * dz
    return gx, gz


def scene_pool():
    s = Scene("pool")
    tiles = s.texture(tile_texture((236, 242, 244), (218, 234, 240), (150, 160, 166)))
    pool_m = s.material("pool_tiles", base=(0.55, 0.80, 0.90), texture=tiles)
    deck_m = s.material("deck", base=(0.62, 0.60, 0.56))
    wall_m = s.material("hall_wall", base=(0.75, 0.75, 0.72))
    ceiling_m = s.material("ceiling", base=(0.80, 0.80, 0.80))
    water_m = glass(s, "water", 1.33)

    PX, PZ, depth, level = 2.0, 1.5, 1.2, -0.12  # pool half extents, depth, water level
    HX, HZ0, HZ1, HH = 4.0, -4.0, 4.5, 3.5       # the hall around it
    tile_repeat = 1.6

    # pool basin: floor and four inner walls, tiled
    basin = s.mesh("pool_basin", pool_m, tile_repeat)
    add_room({"floor": basin, "left": basin, "right": basin, "back": basin, "front": basin},
             (-PX, -depth, -PZ), (PX, 0.0, PZ))
    # the deck around the pool (a frame of four rectangles at y = 0)
    deck = s.mesh("deck", deck_m)
    add_rect(deck, (-HX, 0.0, HZ0), (HX, 0.0, -PZ), (0, 1, 0))
    add_rect(deck, (-HX, 0.0, PZ), (HX, 0.0, HZ1), (0, 1, 0))
    add_rect(deck, (-HX, 0.0, -PZ), (-PX, 0.0, PZ), (0, 1, 0))
    add_rect(deck, (PX, 0.0, -PZ), (HX, 0.0, PZ), (0, 1, 0))
    walls = s.mesh("hall_walls", wall_m)
    add_room({"ceiling": s.mesh("ceiling", ceiling_m), "left": walls, "right": walls,
              "back": walls, "front": walls}, (-HX, 0.0, HZ0), (HX, HH, HZ1))

    # the water: one surface spanning the basin exactly (its edges lie on the basin walls)
    water = s.mesh("water", water_m)
    add_heightfield(water, -PX, PX, -PZ, PZ, 64, 48,
                    lambda x, z: wave_height(x, z, level), wave_gradient)

    # the lamp: 20 cm square, facing down, above the pool and off-centre (small, so that the
    # caustics on the pool floor stay sharp)
    lamp = s.mesh("light", light(s, 600.0))
    add_rect(lamp, (-0.5, HH - 0.002, -0.8), (-0.3, HH - 0.002, -0.6), (0, -1, 0))

    s.look_at((0.4, 1.9, 3.3), (-0.2, -1.0, -0.6), 55.0)
    s.must_see = ["water", "pool_basin", "deck", "hall_walls"]
    s.open_glass = ["water"]
    return s


SCENES = {
    "cornell": scene_cornell,
    "cornell-glass": scene_cornell_glass,
    "cornell-point": scene_cornell_point,
    "door-ajar": scene_door_ajar,
    "bathroom": scene_bathroom,
    "pool": scene_pool,
}


# --------------------------------------------------------------------------------------------
# --check: re-read the written files and verify them


COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}
CTYPES = {5121: ("B", 1), 5123: ("H", 2), 5125: ("I", 4), 5126: ("f", 4)}


def read_accessor(doc, blob, index):
    acc = doc["accessors"][index]
    view = doc["bufferViews"][acc["bufferView"]]
    fmt, size = CTYPES[acc["componentType"]]
    n = COMPONENTS[acc["type"]]
    stride = view.get("byteStride", size * n)
    start = view["byteOffset"] + acc.get("byteOffset", 0)
    need = stride * (acc["count"] - 1) + size * n
    if start % size:
        raise ValueError("accessor %d is not aligned" % index)
    if acc.get("byteOffset", 0) + need > view["byteLength"]:
        raise ValueError("accessor %d runs past its bufferView" % index)
    out = []
    for i in range(acc["count"]):
        v = struct.unpack_from("<%d%s" % (n, fmt), blob, start + i * stride)
        out.append(v if n > 1 else v[0])
    return out


def ray_triangle(o, d, p0, p1, p2):
    e1 = sub(p1, p0)
    e2 = sub(p2, p0)
    pv = cross(d, e2)
    det = dot(e1, pv)
    if abs(det) < 1e-12:
        return None
    inv = 1.0 / det
    tv = sub(o, p0)
    u = dot(tv, pv) * inv
    if u < 0.0 or u > 1.0:
        return None
    qv = cross(tv, e1)
    v = dot(d, qv) * inv
    if v < 0.0 or u + v > 1.0:
        return None
    t = dot(e2, qv) * inv
    return t if t > 1e-6 else None


def ray_box(o, inv, lo, hi, tmax):
    t0, t1 = 0.0, tmax
    for i in range(3):
        a = (lo[i] - o[i]) * inv[i]
        b = (hi[i] - o[i]) * inv[i]
        if a > b:
            a, b = b, a
        t0 = max(t0, a)
        t1 = min(t1, b)
        if t0 > t1:
            return False
    return True


class Caster:
    """Brute-force ray casting over small groups of triangles with bounding boxes."""

    def __init__(self, tris):  # tris: list of (p0, p1, p2, mesh index)
        self.groups = []
        for i in range(0, len(tris), 16):
            g = tris[i:i + 16]
            pts = [p for t in g for p in t[:3]]
            lo = tuple(c - 1e-6 for c in min3(pts))
            hi = tuple(c + 1e-6 for c in max3(pts))
            self.groups.append((lo, hi, g))

    def cast(self, o, d):
        inv = tuple(1.0 / c if c != 0 else 1e30 for c in d)
        best, hit = 1e30, None
        for lo, hi, g in self.groups:
            if not ray_box(o, inv, lo, hi, best):
                continue
            for p0, p1, p2, m in g:
                t = ray_triangle(o, d, p0, p1, p2)
                if t is not None and t < best:
                    best, hit = t, m
        return hit


def check_scene(path, scene):
    """Checks one written scene; returns a list of problems (empty when it is fine)."""
    errors = []
    with open(path, "rb") as f:
        doc = json.loads(f.read().decode("ascii"))
    if doc.get("asset", {}).get("version") != "2.0":
        errors.append("asset.version is not 2.0")
    (buf,) = doc["buffers"]
    with open(os.path.join(os.path.dirname(path), buf["uri"]), "rb") as f:
        blob = f.read()
    if len(blob) != buf["byteLength"]:
        errors.append("buffer byteLength %d != file size %d" % (buf["byteLength"], len(blob)))
    for i, v in enumerate(doc["bufferViews"]):
        if v["byteOffset"] + v["byteLength"] > len(blob):
            errors.append("bufferView %d runs past the buffer" % i)

    # extensions: what the materials use is exactly what extensionsUsed lists
    used = set()
    for m in doc.get("materials", []):
        used.update(m.get("extensions", {}))
    used.update(doc.get("extensions", {}))  # document-level: KHR_lights_punctual
    if used != set(doc.get("extensionsUsed", [])):
        errors.append("extensionsUsed %s != used %s" % (doc.get("extensionsUsed"), sorted(used)))

    tris, names, emissive = [], [], set()
    for node in doc["nodes"]:
        if "mesh" not in node:
            continue
        if any(k in node for k in ("matrix", "translation", "rotation", "scale")):
            errors.append("mesh node %s has a transform (the check assumes none)" % node["name"])
        mesh = doc["meshes"][node["mesh"]]
        for prim in mesh["primitives"]:
            try:
                acc = doc["accessors"][prim["attributes"]["POSITION"]]
                pos = read_accessor(doc, blob, prim["attributes"]["POSITION"])
                nrm = read_accessor(doc, blob, prim["attributes"]["NORMAL"])
                idx = read_accessor(doc, blob, prim["indices"])
                uv = (read_accessor(doc, blob, prim["attributes"]["TEXCOORD_0"])
                      if "TEXCOORD_0" in prim["attributes"] else None)
            except (ValueError, KeyError, struct.error) as e:
                errors.append("%s: %s" % (mesh["name"], e))
                continue
            lo = [min(p[i] for p in pos) for i in range(3)]
            hi = [max(p[i] for p in pos) for i in range(3)]
            if acc.get("min") != lo or acc.get("max") != hi:
                errors.append("%s: POSITION min/max do not match the data" % mesh["name"])
            if len(nrm) != len(pos) or (uv is not None and len(uv) != len(pos)):
                errors.append("%s: attribute counts differ" % mesh["name"])
            if any(abs(length(n) - 1.0) > 1e-4 for n in nrm):
                errors.append("%s: a normal is not unit length" % mesh["name"])
            if len(idx) % 3 or max(idx) >= len(pos):
                errors.append("%s: index out of range or not triangles" % mesh["name"])
                continue
            mat = doc["materials"][prim["material"]]
            if max(mat.get("emissiveFactor", [0, 0, 0])) > 0:
                emissive.add(len(names))
            transmissive = "KHR_materials_transmission" in mat.get("extensions", {})
            if transmissive and mesh["name"] not in scene.open_glass:
                # a dielectric must enclose a volume: welded by position, every edge is shared
                # by exactly two triangles, once in each direction
                key = [tuple(round(c, 5) for c in p) for p in pos]
                edges = {}
                for t in range(0, len(idx), 3):
                    for a, b in ((0, 1), (1, 2), (2, 0)):
                        e = (key[idx[t + a]], key[idx[t + b]])
                        edges[e] = edges.get(e, 0) + 1
                if any(c != 1 or edges.get((e[1], e[0])) != 1 for e, c in edges.items()):
                    errors.append("%s: glass mesh is not closed" % mesh["name"])
            for t in range(0, len(idx), 3):
                p0, p1, p2 = pos[idx[t]], pos[idx[t + 1]], pos[idx[t + 2]]
                gn = cross(sub(p1, p0), sub(p2, p0))
                if length(gn) < 1e-10:
                    errors.append("%s: degenerate triangle %d" % (mesh["name"], t // 3))
                    break
                # the winding agrees with the shading normals
                ns = add(add(nrm[idx[t]], nrm[idx[t + 1]]), nrm[idx[t + 2]])
                if dot(gn, ns) <= 0:
                    errors.append("%s: triangle %d winding disagrees with its normals"
                                  % (mesh["name"], t // 3))
                    break
                tris.append((p0, p1, p2, len(names)))
        names.append(mesh["name"])

    # the camera
    cams = [n for n in doc["nodes"] if n.get("name") == "main" and "camera" in n]
    if len(cams) != 1:
        errors.append("no single camera node named main")
        return errors
    node = cams[0]
    cam = doc["cameras"][node["camera"]]
    if cam["type"] != "perspective" or cam.get("name") != "main":
        errors.append("camera main is not a perspective camera named main")
        return errors
    q = node["rotation"]
    if abs(math.sqrt(sum(c * c for c in q)) - 1.0) > 1e-5:
        errors.append("camera rotation is not a unit quaternion")
    x, y, z, w = q

    def rotate(v):  # v rotated by q
        u = (x, y, z)
        t = mul(cross(u, v), 2.0)
        return add(add(v, mul(t, w)), cross(u, t))

    eye = tuple(node["translation"])
    tan_y = math.tan(cam["perspective"]["yfov"] / 2)
    tan_x = tan_y * cam["perspective"].get("aspectRatio", ASPECT)
    caster = Caster(tris)
    nx, ny = 32, 24
    hits = [0] * len(names)
    misses = 0
    for j in range(ny):
        for i in range(nx):
            sx = ((i + 0.5) / nx * 2 - 1) * tan_x
            sy = (1 - (j + 0.5) / ny * 2) * tan_y
            m = caster.cast(eye, normalize(rotate((sx, sy, -1.0))))
            if m is None:
                misses += 1
            else:
                hits[m] += 1
    total = nx * ny
    if misses > 0.01 * total:
        errors.append("%d of %d camera rays see nothing" % (misses, total))
    light_share = sum(hits[m] for m in emissive) / total
    if light_share > scene.max_light_fraction:
        errors.append("an emitter covers %.1f%% of the image (at most %.1f%%)"
                      % (100 * light_share, 100 * scene.max_light_fraction))
    for name in scene.must_see:
        if name not in names:
            errors.append("no mesh named %s" % name)
        elif hits[names.index(name)] == 0:
            errors.append("the camera does not see %s" % name)
    # closed: rays from the camera in all directions hit something
    n_dirs, escaped = 400, 0
    for k in range(n_dirs):
        yy = 1 - 2 * (k + 0.5) / n_dirs
        r = math.sqrt(1 - yy * yy)
        phi = k * math.pi * (3 - math.sqrt(5))
        if caster.cast(eye, (r * math.cos(phi), yy, r * math.sin(phi))) is None:
            escaped += 1
    if escaped:
        errors.append("%d of %d rays from the camera escape the scene" % (escaped, n_dirs))
    return errors


# --------------------------------------------------------------------------------------------


def main(argv):
    out, check, names = HERE, False, []
    args = list(argv)
    while args:
        a = args.pop(0)
        if a == "--out":
            out = os.path.abspath(args.pop(0))
        elif a == "--check":
            check = True
        elif a in ("-h", "--help"):
            print(__doc__)
            return 0
        elif a in SCENES:
            names.append(a)
        else:
            print("unknown argument %r (scenes: %s)" % (a, ", ".join(SCENE_NAMES)))
            return 2
    names = names or list(SCENE_NAMES)
    failed = False
    for name in names:
        scene = SCENES[name]()
        gltf, blob = scene.to_gltf()
        folder = os.path.join(out, name)
        path = os.path.join(folder, name + ".gltf")
        if check:
            problems = []
            try:
                with open(path, "rb") as f:
                    on_disk = f.read()
                with open(os.path.join(folder, name + ".bin"), "rb") as f:
                    on_disk_bin = f.read()
                if on_disk != gltf or on_disk_bin != blob:
                    problems.append("files differ from what generate.py writes now (stale?)")
                problems += check_scene(path, scene)
            except (OSError, ValueError, KeyError) as e:
                problems.append(str(e))
            status = "ok" if not problems else "FAILED"
            print("%-14s %6d triangles  %8d bytes bin  %s"
                  % (name, scene.triangle_count(), len(blob), status))
            for p in problems:
                print("    " + p)
            failed = failed or bool(problems)
        else:
            os.makedirs(folder, exist_ok=True)
            with open(path, "wb") as f:
                f.write(gltf)
            with open(os.path.join(folder, name + ".bin"), "wb") as f:
                f.write(blob)
            print("%-14s %6d triangles  %8d bytes bin  -> %s"
                  % (name, scene.triangle_count(), len(blob), os.path.relpath(path)))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
