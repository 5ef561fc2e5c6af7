#!/usr/bin/python3
"""Copy a glTF scene into a directory with every material made diffuse, for render_cycles.py.

    /usr/bin/python3 scripts/cycles/diffuse_variant.py SCENE.gltf OUTDIR   # prints the new path

Prints the path of a scene that is pure Lambert + emission under Partita's mapping
(core/material_mapping.h rule 2): metallicFactor 0, roughnessFactor 1, transmission / volume /
ior extensions removed, base colour kept. Scenes that already are diffuse are copied unchanged
(external buffers and images are copied next to the new file). Textured base colours are not
supported by render_cycles.py and are left for it to reject.
"""
import json
import os
import shutil
import sys

DROP = ("KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_ior",
        "KHR_materials_specular", "KHR_materials_clearcoat", "KHR_materials_sheen")


def is_diffuse(m):
    pbr = m.get("pbrMetallicRoughness", {})
    ext = m.get("extensions", {})
    return (pbr.get("metallicFactor", 1.0) == 0 and "metallicRoughnessTexture" not in pbr
            and ext.get("KHR_materials_transmission", {}).get("transmissionFactor", 0.0) == 0)


def main():
    src, outdir = sys.argv[1], sys.argv[2]
    with open(src) as f:
        g = json.load(f)
    changed = []
    for m in g.get("materials", []):
        if is_diffuse(m):
            continue
        changed.append(m.get("name"))
        pbr = m.setdefault("pbrMetallicRoughness", {})
        pbr["metallicFactor"] = 0.0
        pbr["roughnessFactor"] = 1.0
        pbr.pop("metallicRoughnessTexture", None)
        for e in DROP:
            m.get("extensions", {}).pop(e, None)
    os.makedirs(outdir, exist_ok=True)
    base = os.path.dirname(os.path.abspath(src))
    for item in g.get("buffers", []) + g.get("images", []):
        uri = item.get("uri", "")
        if uri and not uri.startswith("data:"):
            dst = os.path.join(outdir, uri)
            os.makedirs(os.path.dirname(dst), exist_ok=True)
            shutil.copyfile(os.path.join(base, uri), dst)
    name = os.path.splitext(os.path.basename(src))[0] + ("-diffuse" if changed else "") + ".gltf"
    out = os.path.join(outdir, name)
    with open(out, "w") as f:
        json.dump(g, f, indent=1)
    if changed:
        print("made diffuse: " + ", ".join(map(str, changed)), file=sys.stderr)
    print(out)


if __name__ == "__main__":
    main()
