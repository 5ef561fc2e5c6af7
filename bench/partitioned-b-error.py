#!/usr/bin/env python3
"""How much of partitioned's error per partition its normalising constant b_i explains, from
bench/partitioned-study.sh's files (the reference EXRs and the mpp32 JSON), with oiiotool.
    bench/partitioned-b-error.py [DIR] [SCENE...]      (DIR default build-bench/partitioned-study)

A partition's image is b_i times its chains' histogram, so its mean luminance is b_i (f* is
luminance): a relative error e = b_i / b_true - 1 of the pre-pass's estimate scales the whole
partition's image, an error of |e| x rms(reference layer) by itself, which no number of
mutations removes. b_true is the mean luminance of the reference's layer of the type (for the
complement: the combined image's minus the K types' layers'), the reference's own error included.
Per scene and partition (as in the study's table, over the seeds that had it): b_true, the
seeds' relative errors of b_i, the RMSE that error predicts, the RMSE measured and the share of
the measured MSE the prediction is (mean over seeds; the complement has no prediction: its rms is
not a sum of per-layer statistics)."""
import json
import math
import subprocess
import sys

LUM = (0.2126, 0.7152, 0.0722)


def layer_stats(exr):
    """Per layer name ("" for combined): (mean luminance, rms over the RGB values)."""
    out = subprocess.run(["oiiotool", "-v", "--info", exr, "--printstats"], check=True,
                         capture_output=True, text=True).stdout
    names = avg = std = None
    for line in out.splitlines():
        line = line.strip()
        if line.startswith("channel list:"):
            names = [c.strip() for c in line[len("channel list:"):].split(",")]
        elif line.startswith("Stats Avg:"):
            avg = [float(v) for v in line.split(":")[1].split("(")[0].split()]
        elif line.startswith("Stats StdDev:"):
            std = [float(v) for v in line.split(":")[1].split("(")[0].split()]
    layers = {}
    for name, a, s in zip(names, avg, std):
        layer, _, channel = name.rpartition(".")
        layers.setdefault(layer, {})[channel] = (a, s)
    result = {}
    for layer, ch in layers.items():
        mean = sum(w * ch[c][0] for w, c in zip(LUM, "RGB"))
        rms = math.sqrt(sum(ch[c][0] ** 2 + ch[c][1] ** 2 for c in "RGB") / 3)
        result[layer] = (mean, rms)
    return result


def analyse(folder, scene):
    j = json.load(open(f"{folder}/{scene}-mpp32.json"))
    p = next(r for r in j["results"] if r["algorithm"] == "partitioned")
    stats = layer_stats(f"{folder}/{scene}-ref.exr")
    rows = {}
    for seed in p["per_seed"]:
        labels, st = seed["labels"], seed["statistics"]
        types = [e["layer"] for e in seed["partitions"] if e["layer"] != "complement"]
        for g, e in enumerate(seed["partitions"]):
            b = st[f"partition_{g}_b"]
            if e["layer"] == "complement":
                true = stats[""][0] - sum(stats.get(t, (0, 0))[0] for t in types)
                rms = None
            else:
                true, rms = stats.get(e["layer"], (0.0, 0.0))
            rel = b / true - 1 if true > 0 else None
            predicted = abs(rel) * rms if rel is not None and rms is not None else None
            rows.setdefault(e["layer"], []).append((true, rel, predicted, e["rmse"]))
    print(f"\n**{scene}**\n")
    print("| partition | b_true (ref) | b_i / b_true - 1 per seed | RMSE from b_i alone | "
          "RMSE measured | share of MSE from b_i |")
    print("|---|---|---|---|---|---|")
    order = [x["layer"] for x in p["partitions"]]
    for layer in order:
        r = rows[layer]
        rels = ", ".join("-" if x[1] is None else f"{x[1]:+.2f}" for x in r)
        pred = [x[2] for x in r if x[2] is not None]
        meas = [x[3] for x in r]
        share = [x[2] ** 2 / x[3] ** 2 for x in r if x[2] is not None and x[3] > 0]
        print(f"| {layer} | {r[0][0]:.3g} | {rels} | "
              + (f"{sum(pred) / len(pred):.3g}" if pred else "-") + " | "
              + f"{sum(meas) / len(meas):.3g} | "
              + (f"{sum(share) / len(share):.2f}" if share else "-") + " |")


if __name__ == "__main__":
    folder = sys.argv[1] if len(sys.argv) > 1 else "build-bench/partitioned-study"
    scenes = sys.argv[2:] or ["cornell", "cornell-glass", "cornell-point", "door-ajar",
                              "bathroom", "pool"]
    for s in scenes:
        analyse(folder, s)
