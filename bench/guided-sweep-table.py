#!/usr/bin/env python3
"""docs/guided-sweep.md's tables of a sweep.py run with --seeds N > 1 (its DIR/runs.csv):
    bench/guided-sweep-table.py DIR [DIR...] [--base P1=V1,P2=V2] [--value rmse|relmse|seconds]
                                [--runs runs.csv|runs-shape.csv] [--long]

Several DIRs (runs over the same two parameters, e.g. more seeds for some points) are merged;
a point's seeds are then those of every DIR that has it (a cell with other than the most seeds
says how many in brackets).

Three markdown tables, rows param1, columns param2:
  1. the value's mean +- sample standard deviation over the seeds;
  2. paired against the base point (default: the first row's and column's values that are the
     current defaults, radius=10 and y=128 when swept): the mean over seeds of the ratio
     value(point, seed) / value(base, seed), +- its standard error. Every point renders the same
     seeds, and with them the same pre-pass (it does not depend on |Y'|, R or epsilon), so the
     seed-to-seed spread that all points share (the pre-pass's b_i, mostly) cancels in the
     ratio; a ratio whose interval excludes 1 is a difference the unpaired table cannot show;
  3. the mean render seconds.
--long prints one table instead, a row per point: seeds, RMSE and relMSE mean +- std, the paired
RMSE ratio and the mean seconds.
"""
import argparse
import csv
import math
import sys
from collections import defaultdict
from pathlib import Path


def spread(v):
    m = sum(v) / len(v)
    s = math.sqrt(sum((x - m) ** 2 for x in v) / (len(v) - 1)) if len(v) > 1 else float("nan")
    return m, s, s / math.sqrt(len(v))


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("dirs", nargs="+", metavar="DIR")
    p.add_argument("--base", help="P1=V1,P2=V2 (default radius=10,y=128 when both are swept)")
    p.add_argument("--value", default="rmse", choices=("rmse", "relmse", "seconds"))
    p.add_argument("--long", action="store_true", help="one row per point")
    p.add_argument("--runs", default="runs.csv",
                   help="the file in each DIR (runs-shape.csv: bench/guided-sweep-shape-error.py)")
    args = p.parse_args(argv)
    rows, names = [], None
    for d in args.dirs:
        with open(Path(d) / args.runs) as f:
            reader = csv.DictReader(f)
            if names and reader.fieldnames[:2] != names:
                sys.exit(f"guided-sweep-table: {d} sweeps {reader.fieldnames[:2]}, not {names}")
            names = reader.fieldnames[:2]
            rows += list(reader)
    n1, n2 = names
    labels1 = sorted(dict.fromkeys(r[n1] for r in rows), key=float)
    labels2 = sorted(dict.fromkeys(r[n2] for r in rows), key=float)
    by, rel, secs = defaultdict(dict), defaultdict(list), defaultdict(list)
    for r in rows:
        if r["state"] == "done":
            by[(r[n1], r[n2])][r["seed"]] = float(r[args.value])
            rel[(r[n1], r[n2])].append(float(r["relmse"]))
            secs[(r[n1], r[n2])].append(float(r["seconds"]))
    defaults = {"radius": "10", "y": "128", "epsilon": "0.01"}
    base = None
    if args.base:
        parts = dict(x.split("=", 1) for x in args.base.split(","))
        base = (parts[n1], parts[n2])
    elif n1 in defaults and n2 in defaults:
        base = (defaults[n1], defaults[n2])
    elif len(labels1) == 1 and n2 in defaults:
        base = (labels1[0], defaults[n2])
    if base is not None and base not in by:
        sys.exit(f"guided-sweep-table: the base point {n1}={base[0]}, {n2}={base[1]} is not in "
                 f"the sweep")
    seeds = sorted({s for d in by.values() for s in d}, key=int)
    most = max(len(d) for d in by.values())

    def n_note(d):
        return f" ({len(d)})" if len(d) != most else ""

    if args.long:
        print(f"| {n1} | {n2} | seeds | RMSE | relMSE | RMSE / base (paired) | seconds |")
        print("|---:|---:|---:|---:|---:|---:|---:|")
        for l1 in labels1:
            for l2 in labels2:
                d = by.get((l1, l2))
                if not d:
                    continue
                m, s, _ = spread(list(d.values()))
                rm, rs, _ = spread(rel[(l1, l2)])
                ratio = "-"
                if base is not None:
                    b = by[base]
                    ratios = [d[k] / b[k] for k in d if k in b and b[k] > 0]
                    if (l1, l2) == base:
                        ratio = "**1**"
                    elif ratios:
                        rmean, _, rse = spread(ratios)
                        ratio = f"{rmean:.3f} +- {rse:.3f}"
                print(f"| {l1} | {l2} | {len(d)} | {m:.4f} +- {s:.4f} | {rm:.3f} +- {rs:.3f} | "
                      f"{ratio} | {spread(secs[(l1, l2)])[0]:.2f} |")
        return

    head = f"| {n1} \\ {n2} | " + " | ".join(labels2) + " |"
    rule = "|---|" + "---:|" * len(labels2)
    print(f"{args.value}, mean +- std over seeds {seeds[0]}-{seeds[-1]}:\n")
    print(head)
    print(rule)
    for l1 in labels1:
        cells = []
        for l2 in labels2:
            v = list(by[(l1, l2)].values())
            if not v:
                cells.append("-")
                continue
            m, s, _ = spread(v)
            cells.append((f"{m:.4f} +- {s:.4f}" if args.value != "seconds" else f"{m:.2f}")
                         + n_note(v))
        print(f"| {l1} | " + " | ".join(cells) + " |")

    if base is not None and args.value != "seconds":
        print(f"\n{args.value} / {args.value} at {n1}={base[0]}, {n2}={base[1]}, paired by seed, "
              f"mean +- standard error:\n")
        print(head)
        print(rule)
        b = by[base]
        for l1 in labels1:
            cells = []
            for l2 in labels2:
                d = by[(l1, l2)]
                ratios = [d[s] / b[s] for s in seeds if s in d and s in b and b[s] > 0]
                if not ratios:
                    cells.append("-")
                    continue
                m, _, se = spread(ratios)
                text = f"{m:.3f} +- {se:.3f}" if (l1, l2) != base else "**1**"
                cells.append(text + n_note(ratios))
            print(f"| {l1} | " + " | ".join(cells) + " |")

    if args.value != "seconds":
        print("\nrender seconds, mean over seeds:\n")
        print(head)
        print(rule)
        for l1 in labels1:
            cells = [f"{spread(secs[(l1, l2)])[0]:.2f}" if secs[(l1, l2)] else "-"
                     for l2 in labels2]
            print(f"| {l1} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
