# Render a glTF scene with Blender Cycles under exactly Partita's light-transport model, as an
# independent reference for Partita's path tracer (`pt`).
#
#   nice -n 19 blender -b -noaudio --factory-startup -t 1 -P scripts/cycles/render_cycles.py -- \
#       --scene scenes/cornell/cornell.gltf --width 128 --height 128 --spp 64 --seed 1 \
#       --max-depth 16 --out /tmp/cycles-x/ref.exr
#
# Writes two EXRs (float32, linear, channels R,G,B):
#   --out            W x H, directly comparable with Partita's combined layer (see "Pixel filter").
#   <out>.raw.exr    the raw Cycles render it was made from: (W+2) x (H+2) pixels supersampled k x k
#                    (--supersample, default 4), one pixel of overscan on every side; compare.py
#                    uses it to estimate variances (its cells are independent, the W x H pixels
#                    share cells and are not).
#
# What is matched to Partita (core/material_mapping.h, core/light.h, core/camera.cpp,
# core/integrators/pt/):
#   * Materials. Partita maps a non-metallic, non-transmissive glTF material to Lambert(baseColor)
#     (rule 2) and gives emissive triangles radiance emissiveFactor x emissiveStrength. Every
#     material is replaced by a pure Diffuse BSDF (roughness 0 = Lambert, not Oren-Nayar) of the
#     glTF baseColorFactor, plus for emissive materials an Emission shader. Base colour and
#     emission are read from the glTF JSON and cross-checked against what Blender's importer put in
#     the Principled BSDF node (Base Color, Emission, Emission Strength). A metallic, transmissive
#     or textured material aborts the render: this comparison is for diffuse scenes only.
#   * Emission units. A Cycles Emission shader of colour c and strength s seen directly renders
#     as the pixel value c x s: its Strength is radiance for mesh emitters (W/(m^2 sr) relative
#     units, no pi, no area factor). So the conversion factor is 1: strength = emissiveStrength,
#     colour = emissiveFactor (EMISSION_UNIT_FACTOR below). Verified by run.sh's unit test: a
#     camera looking straight at an emissive quad of emissiveFactor (1,1,1), strength 1, gives
#     1.0 in every pixel in both renderers.
#   * One-sided emitters. Partita's area lights emit from the front face (counter-clockwise
#     winding) only, unless the material is doubleSided (core/render_scene.cpp: twoSided =
#     doubleSided). Cycles emission is two-sided, so for a one-sided material the emission is
#     mixed to black by Geometry.Backfacing (Cycles evaluates the shader with the backfacing flag
#     for next-event samples too, so light sampling agrees).
#   * Depth. Partita's --max-depth N allows N scattering vertices: with N = 1 a path is
#     camera -> surface -> light (direct light only, LDE), emission seen directly (LE) needs 0.
#     Cycles' max_bounces counts bounces after the first hit: 0 = direct light only. So
#     max_bounces = diffuse_bounces = N - 1 (run.sh checks the convention at N = 1 and 2).
#   * Camera. The glTF camera node (its transform via the importer); the vertical field of view
#     is the glTF yfov and the image's own aspect ratio wins over the file's hint (square pixels),
#     as in Partita's Camera. sensor_fit = VERTICAL, no shift, near clip 1e-5 (Partita: none).
#   * Pixel filter. Partita samples each pixel's rays from a separable tent of radius 1 pixel
#     around the pixel centre (filter importance sampling: the pixel value is the tent-weighted
#     integral of radiance over 2 x 2 pixels). Cycles has no tent filter, so Cycles renders a box
#     filter of width 1 at k x k cells per pixel (k even, so cell edges fall on the tent's kinks)
#     with one pixel of overscan, and each output pixel is sum(cell value x integral of the tent
#     over the cell). The remaining error is that of treating radiance as constant over a cell
#     of 1/k pixel (at k = 4: well below the noise of block averages, see README).
#   * No clamping, no denoising, no adaptive sampling, no path guiding, no light threshold,
#     no filter glossy, black world, film exposure 1, view transform Standard (irrelevant for EXR,
#     which Blender writes linear and unmodified), one thread.
import argparse
import json
import math
import os
import sys
import time

import bpy
import numpy as np

EMISSION_UNIT_FACTOR = 1.0  # Cycles Emission strength per unit of glTF emissive radiance


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="render_cycles.py")
    p.add_argument("--scene", required=True)
    p.add_argument("--width", type=int, default=128)
    p.add_argument("--height", type=int, default=128)
    p.add_argument("--spp", type=int, default=16, help="Cycles samples per supersampled cell")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--max-depth", type=int, default=16,
                   help="in Partita's convention (scattering vertices); Cycles gets N - 1 bounces")
    p.add_argument("--supersample", type=int, default=4, help="k: cells per pixel per axis, even")
    p.add_argument("--threads", type=int, default=1)
    p.add_argument("--out", required=True)
    a = p.parse_args(argv)
    if a.supersample < 2 or a.supersample % 2:
        p.error("--supersample must be even")
    if a.max_depth < 1:
        p.error("--max-depth must be >= 1")
    return a


def fail(msg):
    print("render_cycles.py: error: " + msg, file=sys.stderr)
    sys.stderr.flush()
    os._exit(2)


def gltf_materials(path):
    with open(path) as f:
        g = json.load(f)
    out = {}
    for i, m in enumerate(g.get("materials", [])):
        pbr = m.get("pbrMetallicRoughness", {})
        ext = m.get("extensions", {})
        if "baseColorTexture" in pbr or "emissiveTexture" in m:
            fail("material %r is textured; only constant colours are supported" % m.get("name"))
        metallic = pbr.get("metallicFactor", 1.0)
        transmission = ext.get("KHR_materials_transmission", {}).get("transmissionFactor", 0.0)
        if metallic != 0 or transmission != 0:
            fail("material %r is not diffuse (metallic %g, transmission %g); build a diffuse "
                 "variant first" % (m.get("name"), metallic, transmission))
        strength = ext.get("KHR_materials_emissive_strength", {}).get("emissiveStrength", 1.0)
        out[m.get("name", "material%d" % i)] = {
            "base": [min(max(c, 0.0), 1.0) for c in pbr.get("baseColorFactor", [1, 1, 1, 1])[:3]],
            "emission": [c * strength for c in m.get("emissiveFactor", [0, 0, 0])],
            "double_sided": bool(m.get("doubleSided", False)),
        }
    cams = g.get("cameras", [])
    if not cams or cams[0].get("type") != "perspective":
        fail("the scene's first camera must be perspective")
    return out, cams[0]["perspective"]["yfov"], cams[0].get("name")


def principled_values(mat):
    """(base colour, emission radiance) from the importer's Principled BSDF, or None."""
    if not mat.use_nodes:
        return None
    for n in mat.node_tree.nodes:
        if n.type == "BSDF_PRINCIPLED":
            bc = n.inputs["Base Color"]
            if bc.is_linked:
                fail("material %r: Base Color is linked to a texture" % mat.name)
            base = list(bc.default_value)[:3]
            em = list(n.inputs["Emission"].default_value)[:3]
            s = n.inputs["Emission Strength"].default_value if "Emission Strength" in n.inputs else 1
            # The importer may route emission through an Emission node instead; then the
            # Principled emission is black and the check below is skipped.
            return base, [c * s for c in em]
    return None


def replace_material(mat, spec):
    base, emission, double_sided = spec["base"], spec["emission"], spec["double_sided"]
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    out.target = "ALL"
    diffuse = nt.nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = (*base, 1.0)
    diffuse.inputs["Roughness"].default_value = 0.0  # Lambert
    surface = diffuse.outputs["BSDF"]
    if any(c > 0 for c in emission):
        em = nt.nodes.new("ShaderNodeEmission")
        em.inputs["Color"].default_value = (*emission, 1.0)
        em.inputs["Strength"].default_value = EMISSION_UNIT_FACTOR
        emit = em.outputs["Emission"]
        if not double_sided:
            # Front face only: backfacing -> black emission.
            geo = nt.nodes.new("ShaderNodeNewGeometry")
            black = nt.nodes.new("ShaderNodeEmission")
            black.inputs["Color"].default_value = (0, 0, 0, 1)
            black.inputs["Strength"].default_value = 0.0
            mix = nt.nodes.new("ShaderNodeMixShader")
            nt.links.new(geo.outputs["Backfacing"], mix.inputs["Fac"])
            nt.links.new(emit, mix.inputs[1])
            nt.links.new(black.outputs["Emission"], mix.inputs[2])
            emit = mix.outputs["Shader"]
        if any(c > 0 for c in base):
            add = nt.nodes.new("ShaderNodeAddShader")
            nt.links.new(emit, add.inputs[0])
            nt.links.new(surface, add.inputs[1])
            surface = add.outputs["Shader"]
        else:
            surface = emit  # black Lambert reflects nothing; Partita's light material
    nt.links.new(surface, out.inputs["Surface"])
    mat.cycles.sample_as_light = True


def tent_cell_weights(k):
    """Integral of the unit tent (radius 1 pixel) over each of the 2k cells of width 1/k."""
    def cdf(u):
        return 0.5 * (1 + u) ** 2 if u <= 0 else 1 - 0.5 * (1 - u) ** 2
    edges = [-1 + j / k for j in range(2 * k + 1)]
    return np.array([cdf(edges[j + 1]) - cdf(edges[j]) for j in range(2 * k)])


def tent_reconstruct(raw, width, height, k):
    """raw: ((H+2)k, (W+2)k, 3), top row first, one pixel of overscan. Returns (H, W, 3)."""
    w = tent_cell_weights(k)
    # Pixel x (0-based, unpadded) is centred at cell (x + 1.5) k; its tent covers cells
    # (x + 0.5) k ... (x + 2.5) k - 1.
    off = k // 2
    cols = sum(w[j] * raw[:, off + j: off + j + width * k: k, :] for j in range(2 * k))
    return sum(w[j] * cols[off + j: off + j + height * k: k, :, :] for j in range(2 * k))


def write_exr(path, data, meta):
    """Writes an H x W x 3 float32 array as a zip-compressed RGB EXR with string metadata."""
    import OpenImageIO as oiio
    o = oiio.ImageOutput.create(path)
    spec = oiio.ImageSpec(data.shape[1], data.shape[0], 3, oiio.FLOAT)
    spec.channelnames = ("R", "G", "B")
    spec.attribute("compression", "zip")
    for key, value in meta.items():
        spec.attribute(key, value)
    o.open(path, spec)
    o.write_image(data)
    o.close()


def main():
    a = parse_args()
    scene_path = os.path.abspath(a.scene)
    specs, yfov, cam_name = gltf_materials(scene_path)

    bpy.ops.wm.read_factory_settings(use_empty=True)
    # Debian 12's Blender 3.4 glTF importer still uses np.bool, which numpy 1.24 removed
    # (AttributeError in set_poly_smoothing). Restore the alias in this process only.
    if "bool" not in np.__dict__:
        np.bool = bool
    res = bpy.ops.import_scene.gltf(filepath=scene_path, merge_vertices=False)
    if "FINISHED" not in res:
        fail("glTF import failed")
    scene = bpy.context.scene

    # Materials: cross-check the importer, then replace.
    used = {s.material for o in scene.objects if o.type == "MESH" for s in o.material_slots}
    for mat in used:
        if mat is None:
            fail("a mesh has no material (Partita's default material is not modelled)")
        if mat.name not in specs:
            fail("imported material %r not found in the glTF" % mat.name)
        spec = specs[mat.name]
        pv = principled_values(mat)
        if pv is not None:
            base, em = pv
            if max(abs(x - y) for x, y in zip(base, spec["base"])) > 1e-4:
                fail("material %r: importer base colour %s != glTF %s" % (mat.name, base, spec["base"]))
            if any(c > 0 for c in em) and max(abs(x - y) for x, y in zip(em, spec["emission"])) > 1e-3:
                fail("material %r: importer emission %s != glTF %s" % (mat.name, em, spec["emission"]))
        replace_material(mat, spec)
        print("material %-12s diffuse %s emission %s %s" % (
            mat.name, spec["base"], spec["emission"],
            "two-sided" if spec["double_sided"] else "front only"))
    for o in scene.objects:
        if o.type == "LIGHT":
            fail("punctual light %r: only emissive triangles are supported" % o.name)
        if o.type == "MESH":
            o.cycles.shadow_terminator_geometry_offset = 0.0
            o.cycles.shadow_terminator_offset = 0.0
            o.visible_shadow = o.visible_diffuse = o.visible_camera = True

    # Camera.
    cams = [o for o in scene.objects if o.type == "CAMERA"]
    cam = next((o for o in cams if o.data.name == cam_name or o.name == cam_name), None) or \
        (cams[0] if cams else None)
    if cam is None:
        fail("no camera imported")
    scene.camera = cam
    k, W, H = a.supersample, a.width, a.height
    cam.data.type = "PERSP"
    cam.data.sensor_fit = "VERTICAL"
    # One pixel of overscan on each side, same pixel size as the W x H image of vertical FOV yfov.
    cam.data.angle_y = 2 * math.atan(math.tan(0.5 * yfov) * (H + 2) / H)
    cam.data.shift_x = cam.data.shift_y = 0.0
    cam.data.clip_start = 1e-5
    cam.data.clip_end = 1e6
    cam.data.dof.use_dof = False

    # World: black.
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    bg = world.node_tree.nodes.get("Background")
    bg.inputs["Color"].default_value = (0, 0, 0, 1)
    bg.inputs["Strength"].default_value = 0.0
    scene.world = world

    # Render settings.
    r = scene.render
    r.engine = "CYCLES"
    r.resolution_x, r.resolution_y = (W + 2) * k, (H + 2) * k
    r.resolution_percentage = 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    r.use_border = False
    r.film_transparent = False
    r.use_motion_blur = False
    r.use_compositing = False
    r.use_sequencer = False
    r.threads_mode = "FIXED"
    r.threads = a.threads
    c = scene.cycles
    c.device = "CPU"
    c.feature_set = "SUPPORTED"
    c.samples = a.spp
    c.seed = a.seed
    c.use_animated_seed = False
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.use_guiding = False
    if hasattr(c, "use_light_tree"):  # Blender >= 3.5
        c.use_light_tree = False
    c.direct_light_sampling_type = "MULTIPLE_IMPORTANCE_SAMPLING"
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.light_sampling_threshold = 0.0
    c.blur_glossy = 0.0
    c.caustics_reflective = c.caustics_refractive = True
    bounces = a.max_depth - 1  # Partita's N scattering vertices = Cycles' N - 1 bounces
    c.max_bounces = bounces
    c.diffuse_bounces = bounces
    c.glossy_bounces = bounces
    c.transmission_bounces = bounces
    c.transparent_max_bounces = bounces
    c.volume_bounces = 0
    c.min_light_bounces = 0
    c.min_transparent_bounces = 0
    c.use_fast_gi = False
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    c.film_exposure = 1.0
    c.scrambling_distance = 1.0
    c.auto_scrambling_distance = False
    c.use_layer_samples = "IGNORE"
    for vl in scene.view_layers:
        vl.cycles.use_denoising = False
        vl.use_pass_combined = True
    vs = scene.view_settings
    vs.view_transform = "Standard"
    vs.look = "None"
    vs.exposure = 0.0
    vs.gamma = 1.0
    scene.display_settings.display_device = "sRGB"
    scene.sequencer_colorspace_settings.name = "Linear"
    im = r.image_settings
    im.file_format = "OPEN_EXR"
    im.color_depth = "32"
    im.color_mode = "RGB"
    im.exr_codec = "ZIP"

    out = os.path.abspath(a.out)
    raw_path = (out[:-4] if out.endswith(".exr") else out) + ".raw.exr"
    r.filepath = raw_path
    r.use_file_extension = False
    t0 = time.time()
    bpy.ops.render.render(write_still=True)
    render_seconds = time.time() - t0

    import OpenImageIO as oiio
    inp = oiio.ImageInput.open(raw_path)
    if inp is None:
        fail("cannot read " + raw_path)
    spec = inp.spec()
    raw = inp.read_image(oiio.FLOAT)
    names = list(spec.channelnames)
    inp.close()
    raw = np.stack([raw[:, :, names.index(ch)] for ch in "RGB"], axis=-1).astype(np.float64)
    img = tent_reconstruct(raw, W, H, k).astype(np.float32)

    meta = {
        "cycles:seed": str(a.seed), "cycles:spp_per_cell": str(a.spp),
        "cycles:supersample": str(k), "cycles:overscan": "1",
        "cycles:max_bounces": str(bounces), "cycles:partita_max_depth": str(a.max_depth),
        "cycles:render_seconds": "%.2f" % render_seconds,
    }
    write_exr(out, img, meta)
    # The raw cells too, with the metadata compare.py reads.
    write_exr(raw_path, raw.astype(np.float32), meta)
    print("wrote %s (%dx%d) and %s (%dx%d)" % (out, W, H, raw_path, raw.shape[1], raw.shape[0]))


main()
