#!/usr/bin/env python3
"""Markdown tables of bench/mlt-study.sh's JSON files: one table per scene, one row per
algorithm and budget.   bench/mlt-study-table.py build-bench/mlt-study/*-pt*.json"""
import json
import sys

MUTATIONS = ["bidirectional", "lens", "caustic", "multi_chain"]


def g(x, digits=3):
    return "-" if x is None else f"{x:.{digits}g}"


def per_second(seconds_per_unit):
    if not seconds_per_unit:
        return "-"
    r = 1 / seconds_per_unit
    return f"{r / 1e3:.0f} k" if r < 1e6 else f"{r / 1e6:.2f} M"


def row(r):
    unit = "spp" if r["rate_unit"] == "samples/s" else "mpp"
    budget = (f"{r['spp']:.0f} spp" if "spp" in r else
              f"{r['seconds']:.2f} s = {int(r['units_per_pixel_mean'] + 0.5)} {unit}")
    acc = r["acceptance_per_mutation"]
    share = r["bootstrap_share"]
    return "| " + " | ".join([
        r["algorithm"], budget,
        f"{g(r['rmse_mean'])} +- {g(r['rmse_std'], 2)}",
        f"{g(r['relmse_mean'])} +- {g(r['relmse_std'], 2)}",
        f"{r['seconds_mean']:.2f}",
        per_second(r["seconds_per_unit"]),
        g(r["cost_per_unit_relative"]),
        g(r["rays_per_second_relative"], 2),
        " / ".join(g(acc.get(m), 2) for m in MUTATIONS) if acc else "-",
        f"{100 * share:.0f}%" if share is not None else "-",
        f"{r['peak_rss_mb']:.0f} (+{r['rss_increase_mb']:.0f})",
    ]) + " |"


scenes = {}  # scene -> (reference's own RMSE, [(pt's spp, rows)]), in the order of the files
for path in sys.argv[1:]:
    j = json.load(open(path))
    name = j["scene"].split("/")[-1].removesuffix(".gltf")
    runs = scenes.setdefault(name, (j["reference_rmse"], []))[1]
    runs.append((j["results"][0].get("spp", 0), [row(r) for r in j["results"]]))
for name, (ref, runs) in scenes.items():
    print(f"\n**{name}** (the reference's own RMSE: {g(ref, 2)})\n")
    print("| algorithm | budget | RMSE | relMSE | s | units/s | cost x pt | rays/s x pt | "
          "acceptance bidir / lens / caustic / multi-chain | bootstrap | peak RSS MB (+run) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    print("\n".join(r for _, rows in sorted(runs) for r in rows))
