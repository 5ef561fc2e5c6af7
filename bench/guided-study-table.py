#!/usr/bin/env python3
"""Markdown tables of bench/guided-study.sh's, bench/guided-memory.sh's and bench/guided-cost.sh's
output (issue #13).
    bench/guided-study-table.py study [DIR]     (default build-bench/guided-study)
    bench/guided-study-table.py memory [DIR]    (default build-bench/guided-memory)
    bench/guided-study-table.py cost [DIR[,DIR...]]  (default build-bench/guided-cost)
    bench/guided-study-table.py complement [DIR] (default build-bench/guided-study)
study: equal mutations per pixel (mlt, partitioned, guided; RMSE raw and with the reference's own
error taken off: sqrt(RMSE^2 - ref^2) per seed), the sampling cost per mutation, acceptance per
mutation type, equal time (pt, mlt, partitioned, guided), and per scene the partitions (P(i),
b_i, acceptance, V' support, RMSE of mlt, partitioned and guided on each). memory: the peak
increases at 1280x720 (cold and warm), guide_bytes and the guides' times, the resident memory
through the guides phase. cost: CPU time per mutation by difference. complement: mlt's error per
type by the move guided uses there, and the complement's largest types."""
import csv
import glob
import json
import math
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from study_json import SCENES, g, load, pm, result, stat_mean, units  # noqa: E402

CAUSTIC = {"cornell-glass", "bathroom", "pool"}
MB = 1e6
EQUAL_TIME_VARIANTS = {
    "equal-time": "pt's spp calibrated to mlt's 32-mpp wall time",
    "equal-time-guided": "calibrated to guided's 32-mpp wall time",
    "equal-time-x4": "calibrated to 4 x mlt's 32-mpp wall time",
    "equal-time-x8": "calibrated to 8 x mlt's 32-mpp wall time",
}


def corrected(r, ref):
    """Mean over seeds of sqrt(RMSE^2 - ref^2): the render's own error (the reference's is
    independent of it); 0 where the reference's is larger."""
    return statistics.mean(math.sqrt(max(0.0, s["rmse"] ** 2 - ref ** 2)) for s in r["per_seed"])


def proposed(stats):
    return sum(v for k, v in stats.items() if k.startswith("proposed_"))


def per_proposed_us(r):
    """render_seconds over every mutation proposed (burn-in included), per seed: mean, cv."""
    pixels = None
    v = [s["statistics"]["render_seconds"] / proposed(s["statistics"]) * 1e6 for s in r["per_seed"]
         if proposed(s["statistics"]) > 0]
    if not v:
        return None, None
    m = statistics.mean(v)
    return m, (statistics.stdev(v) / m if len(v) > 1 else 0)


def per_counted_us(r, pixels):
    v = [s["statistics"]["render_seconds"] / (s["statistics"]["mutations"]) * 1e6
         for s in r["per_seed"]]
    m = statistics.mean(v)
    return m, (statistics.stdev(v) / m if len(v) > 1 else 0)


def study(folder):
    rows_mpp, rows_cost, rows_acc, rows_time, per_scene = [], [], [], {}, []
    for scene in SCENES:
        eq = load(f"{folder}/{scene}-mpp32.json")
        et = load(f"{folder}/{scene}-equal-time.json")
        if eq:
            ref = eq["reference_rmse"] or 0
            m, p, q = result(eq, "mlt"), result(eq, "partitioned"), result(eq, "guided")
            cm, cp, cq = corrected(m, ref), corrected(p, ref), corrected(q, ref)
            rows_mpp.append("| " + " | ".join([
                scene + (" (caustic)" if scene in CAUSTIC else ""), g(ref, 2),
                pm(m["rmse_mean"], m["rmse_std"]), pm(p["rmse_mean"], p["rmse_std"]),
                pm(q["rmse_mean"], q["rmse_std"]),
                f"{p['rmse_mean'] / m['rmse_mean']:.2f}",
                f"**{q['rmse_mean'] / m['rmse_mean']:.2f}**",
                f"{cp / cm:.2f} / **{cq / cm:.2f}**",
                f"{q['rmse_mean'] / p['rmse_mean']:.2f}",
                f"{g(m['relmse_mean'])} / {g(p['relmse_mean'])} / {g(q['relmse_mean'])}",
                f"{m['seconds_mean']:.2f} ({stat_mean(m, 'bootstrap_seconds'):.2f})",
                f"{p['seconds_mean']:.2f} ({stat_mean(p, 'prepass_seconds'):.2f})",
                f"{q['seconds_mean']:.2f} ({stat_mean(q, 'prepass_seconds'):.2f} + "
                f"{stat_mean(q, 'guide_seconds'):.2f})",
            ]) + " |")
            pixels = eq["width"] * eq["height"]
            um, cvm = per_counted_us(m, pixels)
            up, cvp = per_counted_us(p, pixels)
            uq, cvq = per_counted_us(q, pixels)
            am, _ = per_proposed_us(m)
            ap, cvap = per_proposed_us(p)
            aq, cvaq = per_proposed_us(q)
            rows_cost.append("| " + " | ".join([
                scene,
                f"{um:.2f} ({cvm:.2f})", f"{up:.2f} ({cvp:.2f})", f"{uq:.2f} ({cvq:.2f})",
                f"{uq / um:.2f}",
                f"{am:.2f}", f"{ap:.2f} ({cvap:.2f})", f"{aq:.2f} ({cvaq:.2f})",
                f"**{aq / am:.2f}**", f"{aq / ap:.2f}",
            ]) + " |")
            acc = [x["acceptance_per_mutation"] for x in (m, p, q)]
            rows_acc.append("| " + " | ".join([
                scene,
                *[f"{g(a.get('bidirectional'), 2)}" for a in acc],
                g(acc[0].get("lens"), 2), g(acc[1].get("lens"), 2), f"**{g(acc[2].get('guided'), 2)}**",
                *[f"{g(a.get('caustic'), 2)}" for a in acc],
                *[f"{g(a.get('multi_chain'), 2)}" for a in acc],
                f"{g(m['acceptance'], 2)} / {g(p['acceptance'], 2)} / {g(q['acceptance'], 2)}",
            ]) + " |")
            per_scene.append((scene, eq, m, p, q))
        for variant in EQUAL_TIME_VARIANTS:
            et = load(f"{folder}/{scene}-{variant}.json")
            if not et:
                continue
            t, m, p, q = (result(et, a) for a in ("pt", "mlt", "partitioned", "guided"))
            if not all((t, m, p, q)):
                continue
            rows_time.setdefault(variant, []).append("| " + " | ".join([
                scene, f"{t['spp']:.0f} spp = {t['seconds_mean']:.2f} s",
                pm(t["rmse_mean"], t["rmse_std"]),
                f"{pm(m['rmse_mean'], m['rmse_std'])} ({units(m)})",
                f"{pm(p['rmse_mean'], p['rmse_std'])} ({units(p)})",
                f"{pm(q['rmse_mean'], q['rmse_std'])} ({units(q)})",
                f"**{q['rmse_mean'] / m['rmse_mean']:.2f}**",
                f"{q['rmse_mean'] / t['rmse_mean']:.2f}",
                f"{p['rmse_mean'] / m['rmse_mean']:.2f}",
                f"{m['seconds_mean']:.2f} / {p['seconds_mean']:.2f} / {q['seconds_mean']:.2f}",
                f"{stat_mean(q, 'startup_seconds'):.2f}",
            ]) + " |")
    print("Equal mutations per pixel (32), RMSE of the combined image, mean +- std over 4 seeds; "
          "ratios of the means; corrected: the reference's own error taken off per seed:\n")
    print("| scene | ref | mlt | partitioned | guided | partitioned / mlt | guided / mlt "
          "| corrected partitioned / mlt, guided / mlt | guided / partitioned "
          "| relMSE mlt / partitioned / guided | mlt s (bootstrap) | partitioned s (pre-pass) "
          "| guided s (pre-pass + guides) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    print("\n".join(rows_mpp))
    print("\nSampling cost in the same runs: us per counted mutation (the harness's us/unit: "
          "render_seconds / mutations; cv over the 4 seeds), and us per proposed mutation "
          "(render_seconds / every mutation proposed, the partitioned methods' 1024 burn-in "
          "mutations per chain included; wall clock, 2 threads):\n")
    print("| scene | mlt us/unit | partitioned us/unit | guided us/unit | guided / mlt (harness) "
          "| mlt us/proposed | partitioned us/proposed | guided us/proposed "
          "| guided / mlt per proposed | guided / partitioned per proposed |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    print("\n".join(rows_cost))
    print("\nAcceptance per mutation type (mean over seeds) at 32 mpp; guided's guided move "
          "replaces the lens perturbation (its E S* L fallback to the lens perturbation counts as "
          "guided):\n")
    print("| scene | bidir mlt | bidir part. | bidir guided | lens mlt | lens part. | guided move "
          "| caustic mlt | caustic part. | caustic guided | multi mlt "
          "| multi part. | multi guided | overall mlt / part. / guided |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    print("\n".join(rows_acc))
    for variant, rows in rows_time.items():
        print(f"\nEqual time ({variant}: {EQUAL_TIME_VARIANTS[variant]}; mlt, partitioned and "
              "guided get pt's mean wall time), RMSE mean +- std over 4 seeds (mpp reached):\n")
        print("| scene | pt spp = time | pt | mlt (mpp) | partitioned (mpp) | guided (mpp) "
              "| guided / mlt | guided / pt | partitioned / mlt | s taken mlt / part. / guided "
              "| guided start-up s |")
        print("|---|---|---|---|---|---|---|---|---|---|---|")
        print("\n".join(rows))
    for scene, eq, m, p, q in per_scene:
        partitions_table(scene, eq, m, p, q)


def supports(r):
    """Per partition label: the mean over seeds of guided's V' support fraction."""
    out = {}
    for s in r["per_seed"]:
        for key, label in s["labels"].items():
            if key.startswith("partition_") and key.endswith("_type"):
                g_ = key[len("partition_"):-len("_type")]
                v = s["statistics"].get(f"partition_{g_}_guide_support")
                if v is not None:
                    out.setdefault(label, []).append(v)
    return {k: statistics.mean(v) for k, v in out.items()}


def per_seed_partitions(r):
    """{(seed, layer): rmse}."""
    return {(s["seed"], x["layer"]): x for s in r["per_seed"] for x in s.get("partitions", [])}


def partitions_table(scene, eq, m, p, q):
    mine = {x["layer"]: x for x in m.get("partitions", [])}
    parts_p = {x["layer"]: x for x in p["partitions"]}
    sup = supports(q)
    ps, qs = per_seed_partitions(p), per_seed_partitions(q)
    same = all(ps.get(k) is not None for k in qs) and len(ps) == len(qs)
    print(f"\n**{scene}** (pre-pass {q['per_seed'][0]['labels'].get('prepass', '?').split(':')[0]}; "
          f"{stat_mean(q, 'prepass_types'):.0f} types; shares sum to mlt "
          f"{g(m.get('partition_error_share_sum_mean'), 2)}, partitioned "
          f"{g(p.get('partition_error_share_sum_mean'), 2)}, guided "
          f"{g(q.get('partition_error_share_sum_mean'), 2)}; guided's partitions "
          f"{'are' if same else 'are NOT'} partitioned's in every seed)\n")
    print("| partition | seeds | P(i) | b_i | acceptance part. / guided | V' support | mutations "
          "| mlt RMSE | partitioned RMSE | guided RMSE | guided / mlt | guided / part. "
          "| share mlt / part. / guided | ref's own |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for x in q["partitions"]:
        y, z = mine.get(x["layer"]), parts_p.get(x["layer"])
        print("| " + " | ".join([
            x["layer"] + ("" if x["in_reference"] else " (not in ref)"), str(x["seeds"]),
            g(x["p"]), g(x["b"]),
            f"{g(z['acceptance'], 2) if z else '-'} / {g(x['acceptance'], 2)}",
            g(sup.get(x["layer"]), 2),
            f"{x['mutations_mean']:.0f}",
            pm(y["rmse_mean"], y["rmse_std"]) if y else "-",
            pm(z["rmse_mean"], z["rmse_std"]) if z else "-",
            pm(x["rmse_mean"], x["rmse_std"]),
            f"{x['rmse_mean'] / y['rmse_mean']:.2f}" if y and y["rmse_mean"] else "-",
            f"{x['rmse_mean'] / z['rmse_mean']:.2f}" if z and z["rmse_mean"] else "-",
            f"{g(y['error_share_mean'], 2) if y else '-'} / "
            f"{g(z['error_share_mean'], 2) if z else '-'} / {g(x['error_share_mean'], 2)}",
            g(x["reference_rmse"], 2),
        ]) + " |")


def guided_move(t):
    """Which move replaces the lens perturbation on a path of type t (light-to-eye, e.g.
    "LSDSE"): "guided" for E S* D followed by a D or the light (x_s and a connectable x_{s+1});
    "lens" for E S* L (the guided move's fallback); "none" for E S* D S ... (x_{s+1} specular:
    neither the lens perturbation nor the guided move applies, as in LensPerturbation::appliesTo)."""
    rest = t[:-1].rstrip("S")  # drop E, then the camera-side specular chain
    if rest.endswith("L"):
        return "lens"
    return "guided" if rest[:-1][-1:] in ("D", "L") else "none"


def complement(folder):
    """Per scene: mlt's error (its type layers at 32 mpp, mean over the seeds that kept each) by
    the move that guided uses on the type, and the types outside guided's K that hold most of it."""
    print("| scene | mlt's MSE in types where the guided move applies / lens fallback (E S* L) "
          "/ neither (E S* D S ...) | the complement's largest types in mlt (share of mlt's MSE, "
          "move) |")
    print("|---|---|---|")
    for scene in SCENES:
        eq = load(f"{folder}/{scene}-mpp32.json")
        if not eq:
            continue
        m, q = result(eq, "mlt"), result(eq, "guided")
        ks = set()
        for sd in q["per_seed"]:
            ks |= {v for k, v in sd["labels"].items() if k.endswith("_type")}
        total = m["rmse_mean"] ** 2
        by = {"guided": 0.0, "lens": 0.0, "none": 0.0}
        outside = []
        for l in m["layers"]:
            if l["layer"] in ("combined", "other"):
                continue
            share = l["rmse_mean"] ** 2 / total
            by[guided_move(l["layer"])] += share
            if l["layer"] not in ks:
                outside.append((share, l["layer"], l["seeds"]))
        outside.sort(reverse=True)
        print("| " + " | ".join([
            scene, " / ".join(f"{by[k]:.2f}" for k in ("guided", "lens", "none")),
            ", ".join(f"{t} {sh:.2f} ({guided_move(t)}{'' if n == 4 else f', {n} seeds'})"
                      for sh, t, n in outside[:5]),
        ]) + " |")


def timeline(folder, scene, size, a):
    """From the RSS timeline and the progress bar's events (MiB): the peak before the render
    phase's first redraw (pre-pass, guides, chain set-up), the RSS at that redraw, and the peak
    overall. The bar's redraws lag the phases by up to ~0.3 s (a redraw follows a report), so
    only the first "render" redraw is used: by then pre-pass and guides are over."""
    base = f"{folder}/{scene}-{size}-{a}"
    try:
        rows = [(float(r["seconds"]), float(r["rss_mib"]))
                for r in csv.DictReader(open(base + "-rss.csv"))]
        events = [l.rstrip("\n").split("\t", 1) for l in open(base + "-events.txt")]
    except FileNotFoundError:
        return None
    tr = next((float(t) for t, line in events if line.lstrip().startswith("render ")), None)
    if tr is None:
        return None
    before = [r for t, r in rows if t <= tr]
    return {"before_peak": max(before), "render_start": before[-1],
            "peak": max(r for _, r in rows)}


def memory(folder):
    print("| scene | mlt +MB (cold, warm) | partitioned +MB (cold, warm) | guided +MB (cold, warm) | guided - partitioned "
          "| guided - mlt | guide_bytes MB | G-buffer s | denoise s | guide s | pre-pass s "
          "| guided job estimate MB |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    tl_rows = []
    for scene in SCENES:
        for f in sorted(glob.glob(f"{folder}/{scene}-*-guided.json")):
            size = os.path.basename(f)[len(scene) + 1:-len("-guided.json")]
            if not size[0].isdigit():
                continue
            js = {a: load(f"{folder}/{scene}-{size}-{a}.json") for a in ("mlt", "partitioned", "guided")}
            inc = {a: [r["rss_increase_mb"] for r in j["results"]] if j else None for a, j in js.items()}
            qs = [r["per_seed"][0]["statistics"] for r in js["guided"]["results"]]
            def cw(v):
                return "-" if not v else ", ".join(f"+{x:.0f}" for x in v)
            def diff(a, b):
                if not inc[a] or not inc[b]:
                    return "-"
                return ", ".join(f"{x - y:+.0f}" for x, y in zip(inc[a], inc[b]))
            def times(key):
                return ", ".join(f"{s[key]:.2f}" for s in qs)
            print("| " + " | ".join([
                scene, cw(inc["mlt"]), cw(inc["partitioned"]), cw(inc["guided"]),
                diff("guided", "partitioned"), diff("guided", "mlt"),
                f"{qs[0]['guide_bytes'] / MB:.1f}", times("gbuffer_seconds"),
                times("denoise_seconds"), times("guide_seconds"), times("prepass_seconds"),
                g(js["guided"]["results"][0].get("job_memory_estimate_mb"), 4),
            ]) + " |")
            for a in ("partitioned", "guided"):
                t = timeline(folder, scene, size, a)
                if t:
                    tl_rows.append((scene, size, a, t))
    if tl_rows:
        print("\nResident memory (MiB) of partita-local (bench/rss-timeline.py, 2 ms samples; "
              "partita-local resolves a preview every second): the peak before the render phase "
              "(pre-pass, guides, chain set-up), the RSS when the render phase begins, the peak "
              "overall; guided's guides: what it keeps over partitioned when the chains start, "
              "and its transient (its peak before the render over its RSS at the render's "
              "start):\n")
        print("| scene | size | partitioned: peak before render / at render start / peak "
              "| guided: peak before render / at render start / peak | guided keeps over "
              "partitioned | guides' transient |")
        print("|---|---|---|---|---|---|")
        by = {}
        for scene, size, a, t in tl_rows:
            by.setdefault((scene, size), {})[a] = t
        for (scene, size), d in by.items():
            p, q = d.get("partitioned"), d.get("guided")
            if not p or not q:
                continue
            cell = lambda t: f"{t['before_peak']:.0f} / {t['render_start']:.0f} / {t['peak']:.0f}"
            print("| " + " | ".join([
                scene, size, cell(p), cell(q), f"{q['render_start'] - p['render_start']:+.0f}",
                f"+{q['before_peak'] - q['render_start']:.0f}",
            ]) + " |")


def cost(folder):
    rows = []
    for i, f in enumerate(folder.split(",")):  # several folders: their rounds together
        for r in csv.DictReader(open(f"{f}/cost.tsv"), delimiter="\t"):
            r["round"] = f"{i}.{r['round']}"
            rows.append(r)
    key = lambda r: (r["scene"], r["algorithm"], r["round"])
    by = {}
    for r in rows:
        by.setdefault(key(r), {})[int(r["mpp"])] = r
    per = {}  # (scene, algorithm) -> [cpu us per mutation per round], [wall render us ...]
    for (scene, a, rnd), d in by.items():
        lo, hi = min(d), max(d)
        if lo == hi:
            continue
        pixels = int(d[hi]["width"]) * int(d[hi]["height"])
        n = (hi - lo) * pixels
        cpu = (float(d[hi]["user"]) + float(d[hi]["sys"]) - float(d[lo]["user"]) - float(d[lo]["sys"]))
        wall = float(d[hi]["render_seconds"]) - float(d[lo]["render_seconds"])
        per.setdefault((scene, a), ([], []))
        per[(scene, a)][0].append(cpu / n * 1e6)
        per[(scene, a)][1].append(wall / n * 1e6)
    print("| scene | mlt CPU us / mutation (rounds) | partitioned | guided | guided / mlt "
          "| guided / partitioned | wall render_seconds per mutation mlt / part. / guided |")
    print("|---|---|---|---|---|---|---|")
    for scene in SCENES:
        v = {a: per.get((scene, a)) for a in ("mlt", "partitioned", "guided")}
        if not all(v.values()):
            continue
        med = {a: statistics.median(x[0]) for a, x in v.items()}
        wmed = {a: statistics.median(x[1]) for a, x in v.items()}
        cell = lambda a: f"{med[a]:.2f} ({', '.join(f'{x:.2f}' for x in v[a][0])})"
        print("| " + " | ".join([
            scene, cell("mlt"), cell("partitioned"), cell("guided"),
            f"**{med['guided'] / med['mlt']:.2f}**", f"{med['guided'] / med['partitioned']:.2f}",
            " / ".join(f"{wmed[a]:.2f}" for a in ("mlt", "partitioned", "guided")),
        ]) + " |")


if __name__ == "__main__":
    what = sys.argv[1] if len(sys.argv) > 1 else "study"
    default = "study" if what == "complement" else what
    folder = sys.argv[2] if len(sys.argv) > 2 else f"build-bench/guided-{default}"
    {"study": study, "memory": memory, "cost": cost, "complement": complement}[what](folder)
