#!/usr/bin/env python3
"""bench/mlt-sandwich-table.py OUT REF: the table of "Suspicious" 2 (docs/mlt-study.md) from
bench/mlt-sandwich-study.sh's renders in OUT and the references REF/ref-<scene>-128.exr.
Per render: combined RMSE, RMSE of the specular-sandwiched types (every diffuse vertex between
specular ones: the class the lens/caustic/multi-chain perturbations cannot move), and
stuck/type-bound chains, against the BDPT reference. oiiotool only (no numpy here)."""
import re, subprocess, sys, glob, os

def attrs(path):
    out = subprocess.run(["iinfo", "-v", path], capture_output=True, text=True).stdout
    a = {}
    for line in out.splitlines():
        m = re.match(r'\s*partita:(\S+): "?(.*?)"?$', line)
        if m: a[m.group(1)] = m.group(2)
    return a

def layers(path):
    out = subprocess.run(["iinfo", "-v", path], capture_output=True, text=True).stdout
    m = re.search(r"channel list: (.*)", out)
    names = set()
    for ch in m.group(1).split(","):
        ch = ch.strip()
        if ch.endswith(".R"): names.add(ch[:-2])
    return names

def sandwiched(t):
    inner = t[1:-1]
    return "D" in inner and "DD" not in inner and not inner.startswith("D") and not inner.endswith("D")

def stats_sq_sum(args, pixels):
    """Sum over pixels and channels of the squares of an oiiotool --printstats image:
    (avg^2 + std^2) per channel times the pixel count."""
    out = subprocess.run(args + ["--printstats"], capture_output=True, text=True).stdout
    avg = [float(v) for v in re.search(r"Stats Avg: ([0-9.eE+ -]+)", out).group(1).split()]
    std = [float(v) for v in re.search(r"Stats StdDev: ([0-9.eE+ -]+)", out).group(1).split()]
    return sum(a * a + d * d for a, d in zip(avg, std)) * pixels

def channels(layers):
    return ",".join(f"{l}.{c}" for l in layers for c in "RGB")

def sq_error(render, ref, types, rlayers, flayers, pixels):
    """Sum of the squared differences over the given layers; a layer one image lacks is 0 there."""
    both = [t for t in types if t in rlayers and t in flayers]
    only_render = [t for t in types if t in rlayers and t not in flayers]
    only_ref = [t for t in types if t in flayers and t not in rlayers]
    total = 0.0
    if both:
        total += stats_sq_sum(["oiiotool", render, "--ch", channels(both), ref, "--ch",
                               channels(both), "--sub"], pixels)
    if only_render:
        total += stats_sq_sum(["oiiotool", render, "--ch", channels(only_render)], pixels)
    if only_ref:
        total += stats_sq_sum(["oiiotool", ref, "--ch", channels(only_ref)], pixels)
    return total

def main(outdir, refdir):
    print("| scene | seed | mpp | rate | combined RMSE | sandwiched RMSE | stuck / type-bound | acceptance independence | s |")
    print("|---|---|---|---|---|---|---|---|---|")
    for f in sorted(glob.glob(f"{outdir}/*.exr"), key=lambda p: (p.split('/')[-1].split('-s')[0], int(re.search(r'-s(\d+)', p).group(1)), int(re.search(r'-m(\d+)', p).group(1)), p)):
        scene, seed, mpp, rate = re.match(r".*/(\w+)-s(\d+)-m(\d+)-r([0-9.]+)\.exr", f).groups()
        ref = f"{refdir}/ref-{scene}-128.exr"
        a = attrs(f)
        rl, fl = layers(f), layers(ref)
        pixels = 128 * 96
        out = subprocess.run(["oiiotool", f, "--ch", "R,G,B", ref, "--ch", "R,G,B", "--diff"], capture_output=True, text=True).stdout
        comb = float(re.search(r"RMS error = ([0-9.eE+-]+)", out).group(1))
        types = sorted(t for t in (rl | fl) if t != "other" and sandwiched(t))
        se = sq_error(f, ref, types, rl, fl, pixels)
        rmse_s = (se / (pixels * 3)) ** 0.5
        acc = a.get("stat:acceptance_independence", "-")
        print(f"| {scene} | {seed} | {mpp} | {rate} | {comb:.4f} | {rmse_s:.4f} | {a.get('stat:stuck_chains','?')} / {a.get('stat:type_bound_chains','?')} | {acc} | {float(a.get('stat:seconds', 'nan')):.1f} |")
        sys.stdout.flush()

main(sys.argv[1], sys.argv[2])
