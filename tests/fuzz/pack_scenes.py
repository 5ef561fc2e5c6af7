#!/usr/bin/env python3
"""Packs each shipped scene (scenes/*/*.gltf with its external .bin/images) into one
self-contained .glb, so that the fuzzer, which has no files to resolve, can start from them.

usage: tests/fuzz/pack_scenes.py OUTPUT_DIR [SCENES_DIR]
"""
import json
import pathlib
import struct
import sys
import urllib.parse


def pack(gltf_path: pathlib.Path) -> bytes:
    doc = json.loads(gltf_path.read_text())
    blob = bytearray()

    def append(data: bytes) -> int:
        while len(blob) % 4:
            blob.append(0)
        offset = len(blob)
        blob.extend(data)
        return offset

    # Buffers become one BIN chunk: every bufferView is shifted by its buffer's new offset.
    offsets = []
    for buf in doc.get("buffers", []):
        uri = buf.get("uri", "")
        data = (gltf_path.parent / urllib.parse.unquote(uri)).read_bytes() if uri else b""
        offsets.append(append(data))
    for view in doc.get("bufferViews", []):
        view["byteOffset"] = view.get("byteOffset", 0) + offsets[view["buffer"]]
        view["buffer"] = 0
    # External images move into bufferViews as well.
    for image in doc.get("images", []):
        uri = image.pop("uri", None)
        if uri is None or uri.startswith("data:"):
            if uri:
                image["uri"] = uri
            continue
        data = (gltf_path.parent / urllib.parse.unquote(uri)).read_bytes()
        doc.setdefault("bufferViews", []).append(
            {"buffer": 0, "byteOffset": append(data), "byteLength": len(data)})
        image["bufferView"] = len(doc["bufferViews"]) - 1
        image["mimeType"] = "image/jpeg" if uri.lower().endswith((".jpg", ".jpeg")) else "image/png"
    while len(blob) % 4:
        blob.append(0)
    doc["buffers"] = [{"byteLength": len(blob)}] if blob else []

    text = json.dumps(doc, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    chunks = struct.pack("<I4s", len(text), b"JSON") + text
    if blob:
        chunks += struct.pack("<I4s", len(blob), b"BIN\0") + bytes(blob)
    return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks


def main() -> None:
    out = pathlib.Path(sys.argv[1])
    scenes = pathlib.Path(sys.argv[2]) if len(sys.argv) > 2 else \
        pathlib.Path(__file__).resolve().parents[2] / "scenes"
    out.mkdir(parents=True, exist_ok=True)
    for gltf in sorted(scenes.glob("*/*.gltf")):
        (out / (gltf.stem + ".glb")).write_bytes(pack(gltf))
        print(f"packed {gltf} -> {out / (gltf.stem + '.glb')}")


if __name__ == "__main__":
    main()
