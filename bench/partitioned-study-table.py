#!/usr/bin/env python3
"""Markdown tables of bench/partitioned-study.sh's and bench/partitioned-prepass.sh's JSON files.
    bench/partitioned-study-table.py study [DIR]     (default build-bench/partitioned-study)
    bench/partitioned-study-table.py prepass [DIR]   (default build-bench/partitioned-prepass)
study: equal mutations per pixel (mlt, partitioned), equal time (pt, mlt, partitioned), and per
scene the partitions (K types, P(i), b_i, acceptance, error per partition, mlt's error on the
same partitions). prepass: the pre-pass's time, records and memory per scene and size."""
import glob
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from study_json import SCENES, g, load, pm, result, stat_mean, units  # noqa: E402

MIB = 1 << 20


def study(folder):
    rows_mpp, rows_time, per_scene = [], [], []
    for scene in SCENES:
        eq = load(f"{folder}/{scene}-mpp32.json")
        et = load(f"{folder}/{scene}-equal-time.json")
        if eq:
            m, p = result(eq, "mlt"), result(eq, "partitioned")
            rows_mpp.append("| " + " | ".join([
                scene, g(eq["reference_rmse"], 2),
                pm(m["rmse_mean"], m["rmse_std"]), pm(p["rmse_mean"], p["rmse_std"]),
                f"**{p['rmse_mean'] / m['rmse_mean']:.2f}**",
                pm(m["relmse_mean"], m["relmse_std"]), pm(p["relmse_mean"], p["relmse_std"]),
                f"{m['seconds_mean']:.2f} ({stat_mean(m, 'bootstrap_seconds'):.2f})",
                f"{p['seconds_mean']:.2f} ({stat_mean(p, 'prepass_seconds'):.2f})",
                g(p["cost_per_unit_relative"]),
            ]) + " |")
            per_scene.append((scene, eq, m, p))
        if et:
            t, m, p = result(et, "pt"), result(et, "mlt"), result(et, "partitioned")
            rows_time.append("| " + " | ".join([
                scene, f"{t['spp']:.0f} spp = {t['seconds_mean']:.2f} s",
                pm(t["rmse_mean"], t["rmse_std"]),
                f"{pm(m['rmse_mean'], m['rmse_std'])} ({units(m)})",
                f"{pm(p['rmse_mean'], p['rmse_std'])} ({units(p)})",
                f"{p['rmse_mean'] / m['rmse_mean']:.2f}", f"{p['rmse_mean'] / t['rmse_mean']:.2f}",
                f"{m['seconds_mean']:.2f} / {p['seconds_mean']:.2f}",
            ]) + " |")
    print("Equal mutations per pixel (32), RMSE mean +- std over 4 seeds:\n")
    print("| scene | ref | mlt | partitioned | partitioned / mlt | mlt relMSE | partitioned relMSE "
          "| mlt s (bootstrap) | partitioned s (pre-pass) | partitioned's chain time per mutation x mlt's |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    print("\n".join(rows_mpp))
    print("\nEqual time (mlt and partitioned get pt's mean wall time), RMSE mean +- std over 4 "
          "seeds, (mpp reached):\n")
    print("| scene | pt spp = time | pt | mlt (mpp) | partitioned (mpp) | partitioned / mlt "
          "| partitioned / pt | s taken mlt / partitioned |")
    print("|---|---|---|---|---|---|---|---|")
    print("\n".join(rows_time))
    for scene, eq, m, p in per_scene:
        mine = {x["layer"]: x for x in m.get("partitions", [])}
        seeds = p["per_seed"]
        prepass = seeds[0]["labels"].get("prepass", "?")
        print(f"\n**{scene}** (pre-pass {prepass.split(':')[0]}; "
              f"{stat_mean(p, 'prepass_types'):.0f} types in the pre-pass, mean over seeds; "
              f"partition shares sum to {p['partition_error_share_sum_mean']:.2f}, mlt's "
              f"{g(m.get('partition_error_share_sum_mean'), 2)})\n")
        print("| partition | seeds | P(i) | b_i (cv over seeds) | acceptance | mutations | "
              "partitioned RMSE | share | mlt RMSE (seeds) | mlt share | ref's own RMSE |")
        print("|---|---|---|---|---|---|---|---|---|---|---|")
        for x in p["partitions"]:
            y = mine.get(x["layer"])
            cv = x["b_std"] / x["b"] if x["b"] else None
            print("| " + " | ".join([
                x["layer"] + ("" if x["in_reference"] else " (not in ref)"), str(x["seeds"]),
                g(x["p"]), f"{g(x['b'])} ({g(cv, 2)})", g(x["acceptance"], 2),
                f"{x['mutations_mean']:.0f}",
                pm(x["rmse_mean"], x["rmse_std"]), f"{x['error_share_mean']:.2f}",
                f"{pm(y['rmse_mean'], y['rmse_std'])} ({y['seeds']})" if y else "-",
                f"{y['error_share_mean']:.2f}" if y else "-",
                g(x["reference_rmse"], 2),
            ]) + " |")


def prepass(folder):
    print("| scene | size | pre-pass | types | records (bytes) | pre-pass s (runs 1, 2) | "
          "peak RSS MB (+increase run 1, run 2) | estimate MB (of which pre-pass records) | "
          "mlt: bootstrap s, +increase MB, estimate MB |")
    print("|---|---|---|---|---|---|---|---|---|")
    files = {os.path.basename(f)[:-5]: f for f in glob.glob(f"{folder}/*.json")}
    for scene in SCENES:
        sizes = sorted((k[len(scene) + 1:] for k in files
                        if k.startswith(scene + "-") and k[len(scene) + 1:][0].isdigit()
                        and not k.endswith("-mlt")),
                       key=lambda s: int(s.split("x")[0]))
        for size in sizes:
            j = load(files[f"{scene}-{size}"])
            a, b = result(j, "partitioned", 0), result(j, "partitioned", 1)
            s = a["per_seed"][0]["statistics"]
            label = a["per_seed"][0]["labels"].get("prepass", "?").split(":")[0]
            times = [r["per_seed"][0]["statistics"]["prepass_seconds"] for r in (a, b) if r]
            breakdown = a.get("job_memory_estimate_breakdown", "")
            records = breakdown.split("pre-pass records ")[1].split(",")[0] if \
                "pre-pass records " in breakdown else "?"
            print("| " + " | ".join([
                scene, size, label, f"{s['prepass_types']:.0f}",
                f"{s['prepass_records'] / 1e3:.0f} k ({s['prepass_record_bytes'] / MIB:.1f} MiB, "
                f"allocated {s['prepass_record_allocated_bytes'] / MIB:.1f})",
                ", ".join(f"{t:.2f}" for t in times),
                f"{a['peak_rss_mb']:.0f} (+{a['rss_increase_mb']:.0f}"
                + (f", +{b['rss_increase_mb']:.0f})" if b else ")"),
                f"{g(a.get('job_memory_estimate_mb'), 4)} ({records})",
                mlt_cell(load(f"{folder}/{scene}-{size}-mlt.json")),
            ]) + " |")


def mlt_cell(j):
    if not j:
        return "-"
    m = result(j, "mlt")
    return (f"{m['per_seed'][0]['statistics']['bootstrap_seconds']:.2f} s, "
            f"+{m['rss_increase_mb']:.0f}, {g(m.get('job_memory_estimate_mb'), 4)}")


if __name__ == "__main__":
    what = sys.argv[1] if len(sys.argv) > 1 else "study"
    folder = sys.argv[2] if len(sys.argv) > 2 else f"build-bench/partitioned-{what}"
    {"study": study, "prepass": prepass}[what](folder)
