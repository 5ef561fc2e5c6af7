#!/usr/bin/python3
"""Write the tiny glTF scenes of run.sh's unit checks into a directory (standard library only).

    quad-front.gltf  a camera at the origin looking down -Z at an emissive quad (emissiveFactor
                     (1,1,1), strength 1, base colour black) at z = -1 that fills the view, its
                     front face (counter-clockwise winding) towards the camera: every pixel must
                     be 1.0 in both renderers (emission units).
    quad-back.gltf   the same quad wound the other way (one-sided, not doubleSided): every pixel
                     must be 0 (Partita's area lights emit from the front face only).
    quad-double.gltf the back-facing quad with doubleSided true: 1.0 again.
"""
import base64
import json
import os
import struct
import sys


def quad_scene(front, double_sided):
    s = 2.0  # half size: at z = -1 this covers a 90+ degree field of view
    pos = [(-s, -s, -1.0), (s, -s, -1.0), (s, s, -1.0), (-s, s, -1.0)]
    idx = [0, 1, 2, 0, 2, 3] if front else [0, 2, 1, 0, 3, 2]
    nz = 1.0 if front else -1.0
    nrm = [(0.0, 0.0, nz)] * 4
    blob = b"".join(struct.pack("<3f", *p) for p in pos) + b"".join(struct.pack("<3f", *n) for n in nrm)
    blob += struct.pack("<6H", *idx) + b"\0\0"
    uri = "data:application/octet-stream;base64," + base64.b64encode(blob).decode()
    return {
        "asset": {"version": "2.0", "generator": "partita scripts/cycles/make_test_scenes.py"},
        "extensionsUsed": ["KHR_materials_emissive_strength"],
        "buffers": [{"byteLength": len(blob), "uri": uri}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48, "target": 34962},
            {"buffer": 0, "byteOffset": 48, "byteLength": 48, "target": 34962},
            {"buffer": 0, "byteOffset": 96, "byteLength": 12, "target": 34963},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-s, -s, -1.0], "max": [s, s, -1.0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"},
        ],
        "materials": [{
            "name": "light",
            "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0.0,
                                     "roughnessFactor": 1.0},
            "emissiveFactor": [1.0, 1.0, 1.0],
            "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 1.0}},
            "doubleSided": double_sided,
        }],
        "meshes": [{"name": "quad", "primitives": [
            {"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0}]}],
        "cameras": [{"name": "main", "type": "perspective",
                     "perspective": {"yfov": 0.7, "aspectRatio": 1.0, "znear": 0.01}}],
        "nodes": [{"name": "quad", "mesh": 0},
                  {"name": "main", "camera": 0, "translation": [0.0, 0.0, 0.0]}],
        "scenes": [{"nodes": [0, 1]}],
        "scene": 0,
    }


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "."
    os.makedirs(out, exist_ok=True)
    for name, front, ds in (("quad-front", True, False), ("quad-back", False, False),
                            ("quad-double", False, True)):
        with open(os.path.join(out, name + ".gltf"), "w") as f:
            json.dump(quad_scene(front, ds), f, indent=1)


if __name__ == "__main__":
    main()
