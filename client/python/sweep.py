#!/usr/bin/python3
"""Render a grid over two job parameters and measure each image against a reference.

    sweep.py SCENE [--server HOST:PORT] [--param1 radius=2,5,10,20,40] [--param2 y=8,32,128,512]
             [--seeds N] [--algorithm A] [--set NAME=VALUE ...]
             (--reference REF.exr | --reference-spp N [--reference-algorithm A]) [--out-dir DIR]

SCENE is a .gltf/.glb file (uploaded) or a scene name of the server's scene root. The
parameters are a budget (spp, mpp, seconds) or any parameter the algorithm declares (the server
lists them: y, radius, k, epsilon, max-depth, seed, width, height, ...; `partita render
--algorithm A --help` shows A's with their defaults and ranges). The defaults are the paper's Figure 8 study: rows R (radius, pixels), columns |Y'| (y).
--set fixes others for every job (e.g. --set mpp=32 --set width=160). Without --algorithm it
renders with "guided" when the server offers it, else "pt". A parameter the algorithm ignores
(the server says which it reads) is refused, since every image would be the same: with "pt",
sweep e.g. spp and max-depth; |Y'| x R needs the guided method.

--seeds N renders every grid point N times, with seeds S, S+1, ..., S+N-1 (S: --set seed, else
1; the same seeds at every grid point, so that the points can be compared seed by seed) and
reports the mean and spread of the error over them (N = 1, the default: one image a point).

The reference is --reference REF.exr, or with --reference-spp N a render of the same scene,
resolution and depth with N spp by --reference-algorithm (default "pt"; "bdpt" for caustics
from small lights) made first (saved as DIR/reference.exr).

Writes into DIR (default sweep-<scene>):
  sweep.csv    one row per grid point: the two parameters, algorithm, rmse, relmse, seconds, job,
               state; with --seeds N > 1: param1, param2, algorithm, seeds, rmse (the mean over
               seeds), rmse_std (sample standard deviation), rmse_se (standard error, std/sqrt N),
               relmse, relmse_std, relmse_se, seconds (mean), jobs (space-separated), state
  runs.csv     (--seeds N > 1) one row per render: param1, param2, seed, rmse, relmse, seconds,
               job, state
  grid.png     the images, rows = param1, columns = param2, RMSE under each (like Figure 8; with
               seeds, the first seed's image and the mean +- standard error of the RMSE)
  rmse.png     RMSE against param2 (a curve per param1 value) and against render seconds, with
               standard-error bars when N > 1
  renders/     each result's EXR, PNG and JSON metadata (P1=V1_P2=V2[_seed=S].exr)
Without --server it starts a private partitad for the duration (partita_client.LocalDaemon),
running one job at a time so that each job's seconds are its own.
Exit status 0 on success, else one line "sweep.py: error: ..." on stderr.
"""

from __future__ import annotations

import argparse
import csv
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import numpy as np  # noqa: E402

BUDGETS = ("spp", "mpp", "seconds")
# The paper's Figure 8: rows R, columns |Y'|.
DEFAULT_ROWS = "radius=2,5,10,20,40"
DEFAULT_COLUMNS = "y=8,32,128,512"
NAN = float("nan")


class UsageError(Exception):
    pass


def parse_value(name: str, text: str):
    """A whole number, a number, or else the text: the server reads each value with the
    parameter's declaration and names the parameter when one does not fit."""
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    if name in BUDGETS:
        raise UsageError(f"{name}={text}: not a number")
    return text


def parse_axis(text: str):
    name, eq, values = text.partition("=")
    name = name.replace("_", "-")
    if not eq or not name:
        raise UsageError(f"bad parameter '{text}': expected NAME=V1,V2,... with NAME a budget "
                         f"({', '.join(BUDGETS)}) or a parameter of the algorithm")
    items = values.split(",")
    if not values or any(not v for v in items):
        raise UsageError(f"bad parameter '{text}': empty value")
    return name, items, [parse_value(name, v) for v in items]


def kwargs_name(name: str) -> str:
    return name.replace("-", "_")


def srgb8(image: np.ndarray, exposure: float) -> np.ndarray:
    x = np.clip(np.nan_to_num(image * 2.0 ** exposure), 0.0, 1.0)
    s = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
    return (s * 255 + 0.5).astype(np.uint8)


def auto_exposure(image: np.ndarray) -> float:
    lum = image @ np.array([0.2126, 0.7152, 0.0722], dtype=np.float32)
    lum = lum[lum > 0]
    if lum.size == 0:
        return 0.0
    return float(np.log2(0.9 / np.percentile(lum, 99)))


def finite(x: float) -> bool:
    return x == x and x not in (float("inf"), float("-inf"))


def spread(values):
    """mean, sample standard deviation and standard error of the finite values (nan when there
    are none; std and se nan for a single value)."""
    v = [x for x in values if finite(x)]
    if not v:
        return NAN, NAN, NAN
    mean = sum(v) / len(v)
    if len(v) < 2:
        return mean, NAN, NAN
    std = math.sqrt(sum((x - mean) ** 2 for x in v) / (len(v) - 1))
    return mean, std, std / math.sqrt(len(v))


def summarise(runs):
    """One grid point's row from its renders (one per seed)."""
    rmse_m, rmse_s, rmse_e = spread([r["rmse"] for r in runs])
    rel_m, rel_s, rel_e = spread([r["relmse"] for r in runs])
    sec_m, _, _ = spread([r["seconds"] for r in runs])
    bad = [r["state"] for r in runs if r["state"] != "done"]
    # A point's error is the mean over all its seeds: a missing one leaves it undefined.
    if bad or any(not finite(r["rmse"]) for r in runs):
        rmse_m = rmse_s = rmse_e = rel_m = rel_s = rel_e = NAN
    return {"rmse": rmse_m, "rmse_std": rmse_s, "rmse_se": rmse_e, "relmse": rel_m,
            "relmse_std": rel_s, "relmse_se": rel_e, "seconds": sec_m,
            "state": bad[0] if bad else "done"}


def make_figures(out_dir: Path, points, a1, a2, images, reference, seeds: int):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    (n1, labels1, values1), (n2, labels2, values2) = a1, a2
    exposure = auto_exposure(reference)
    fig, axes = plt.subplots(len(values1), len(values2), squeeze=False,
                             figsize=(2.4 * len(values2), 2.1 * len(values1) + 0.4))
    for i, l1 in enumerate(labels1):
        for j, l2 in enumerate(labels2):
            ax = axes[i][j]
            img = images.get((i, j))
            if img is not None:
                ax.imshow(srgb8(img, exposure), interpolation="nearest")
            p = points[(i, j)]
            if not finite(p["rmse"]):
                text = p["state"]
            elif seeds > 1:
                text = f"RMSE {p['rmse']:.4g} ± {p['rmse_se']:.2g}"
            else:
                text = f"RMSE {p['rmse']:.4g}"
            ax.set_xlabel(text, fontsize=8)
            ax.set_xticks([])
            ax.set_yticks([])
            if i == 0:
                ax.set_title(f"{n2}={l2}", fontsize=9)
            if j == 0:
                ax.set_ylabel(f"{n1}={l1}", fontsize=9)
    fig.tight_layout()
    fig.savefig(out_dir / "grid.png", dpi=100)
    plt.close(fig)

    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
    for i, l1 in enumerate(labels1):
        pts = [(values2[j], points[(i, j)]) for j in range(len(labels2))]
        pts = [(x, p) for x, p in pts if finite(p["rmse"])]
        if not pts:
            continue
        ys = [p["rmse"] for _, p in pts]
        err = [p["rmse_se"] if finite(p["rmse_se"]) else 0.0 for _, p in pts] \
            if seeds > 1 else None
        left.errorbar([x for x, _ in pts], ys, yerr=err, fmt="o-", capsize=3,
                      label=f"{n1}={l1}")
        right.errorbar([p["seconds"] for _, p in pts], ys, yerr=err, fmt="o-", capsize=3,
                       label=f"{n1}={l1}")
    spread_note = f" (mean ± s.e. over {seeds} seeds)" if seeds > 1 else ""
    left.set_xlabel(n2)
    left.set_ylabel("RMSE" + spread_note)
    left.set_title(f"RMSE against {n2}")
    right.set_xlabel("render seconds" + (" (mean)" if seeds > 1 else ""))
    right.set_ylabel("RMSE")
    right.set_title("RMSE against time")
    if len(values2) > 1 and all(v > 0 for v in values2) and max(values2) / min(values2) >= 8:
        left.set_xscale("log")
        left.set_xticks(values2)
        left.set_xticklabels(labels2)
        left.minorticks_off()
    for ax in (left, right):
        if any(p["rmse"] > 0 for p in points.values() if finite(p["rmse"])):
            ax.set_yscale("log")
            ax.yaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%.3g"))
            ax.yaxis.set_minor_formatter(matplotlib.ticker.FormatStrFormatter("%.3g"))
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out_dir / "rmse.png", dpi=100)
    plt.close(fig)


def fmt(x: float, digits: int = 8) -> str:
    return f"{x:.{digits}g}"


def run(args) -> int:
    from partita_client import Client, LocalDaemon, PartitaError, read_exr, rmse, rel_mse  # noqa
    from partita_client.scene import is_scene_file

    n1, labels1, values1 = parse_axis(args.param1)
    n2, labels2, values2 = parse_axis(args.param2)
    if n1 == n2:
        raise UsageError(f"--param1 and --param2 both name '{n1}'")
    fixed = {}
    for s in args.set:
        name, eq, value = s.partition("=")
        name = name.replace("_", "-")
        if not eq or not name:
            raise UsageError(f"bad --set '{s}': expected NAME=VALUE with NAME a budget or a "
                             f"parameter of the algorithm")
        fixed[name] = parse_value(name, value)
    if sum(n in BUDGETS for n in {n1, n2, *fixed}) > 1:
        raise UsageError("spp, mpp and seconds all set the budget: give only one of them")
    if args.seeds < 1:
        raise UsageError(f"--seeds {args.seeds}: give at least 1")
    if args.seeds > 1 and "seed" in (n1, n2):
        raise UsageError("--seeds N > 1 with 'seed' as a swept parameter: choose one")
    if not args.reference and not args.reference_spp:
        raise UsageError("give --reference REF.exr or --reference-spp N")
    if is_scene_file(args.scene) and not Path(args.scene).is_file():
        raise UsageError(f"scene file '{args.scene}' does not exist")
    reference = None
    if args.reference:
        reference = read_exr(args.reference).layers()["combined"]

    stem = Path(args.scene).stem if is_scene_file(args.scene) else Path(args.scene).name
    out_dir = Path(args.out_dir or f"sweep-{stem}")
    (out_dir / "renders").mkdir(parents=True, exist_ok=True)
    seeds = args.seeds
    first_seed = fixed.get("seed", 1)
    seed_list = [first_seed + s for s in range(seeds)]

    daemon = None
    if not args.server:
        # One job at a time: jobs share the daemon's threads, so concurrent jobs would each
        # report the time of two.
        daemon = LocalDaemon(threads=args.threads, extra_args=["--max-jobs", "1"])
    try:
        client = Client(daemon.address if daemon else args.server, token_file=args.token_file,
                        tls_ca=args.tls_ca)
        algorithm = args.algorithm
        if not algorithm:
            offered = client.algorithms()
            algorithm = "guided" if "guided" in offered or not offered else "pt"
            if algorithm != "guided":
                print(f"sweep.py: the server has no 'guided' algorithm; sweeping '{algorithm}'",
                      file=sys.stderr)
        reads = client.algorithm_parameters(algorithm)
        for flag, name in (("--param1", n1), ("--param2", n2), *(("--set", n) for n in fixed)):
            if reads and name not in reads:
                raise UsageError(f"{flag} {name}: algorithm '{algorithm}' ignores {name}, so "
                                 f"every image would be the same ({algorithm} reads "
                                 f"{', '.join(reads)})")
        label = args.label or f"sweep.py:{stem}"
        base = {kwargs_name(k): v for k, v in fixed.items()}

        if reference is None:
            ref_params = {k: v for k, v in base.items() if k in ("width", "height", "max_depth")}
            ref_id = client.submit(args.scene, algorithm=args.reference_algorithm,
                                   spp=args.reference_spp,
                                   seed=987654321, label=label + ":reference", **ref_params)
            reference = client.result(ref_id)["combined"]
            client.download(ref_id, out_dir / "reference.exr")

        cells = []
        for i, v1 in enumerate(values1):
            for j, v2 in enumerate(values2):
                for seed in seed_list:
                    params = dict(base)
                    for n in (n1, n2):
                        if n in BUDGETS:
                            for b in BUDGETS:
                                params.pop(b, None)
                    params[kwargs_name(n1)] = v1
                    params[kwargs_name(n2)] = v2
                    if seeds > 1:
                        params["seed"] = seed
                    job_id = client.submit(args.scene, algorithm=algorithm, label=label, **params)
                    cells.append((i, j, seed, job_id))

        runs, images = {}, {}
        for k, (i, j, seed, job_id) in enumerate(cells):
            job = client.wait(job_id)
            run_row = {"seed": seed, "rmse": NAN, "relmse": NAN,
                       "seconds": job.seconds if job.seconds is not None else NAN,
                       "job": job_id, "state": job.state}
            if job.state == "done":
                combined = client.result(job_id, wait=False)["combined"]
                if (i, j) not in images:
                    images[(i, j)] = combined
                name = f"{n1}={labels1[i]}_{n2}={labels2[j]}"
                if seeds > 1:
                    name += f"_seed={seed}"
                client.download(job_id, out_dir / "renders" / f"{name}.exr")
                if combined.shape == reference.shape:
                    run_row["rmse"] = rmse(combined, reference)
                    run_row["relmse"] = rel_mse(combined, reference)
            runs.setdefault((i, j), []).append(run_row)
            if not args.quiet:
                seed_note = f" seed={seed}" if seeds > 1 else ""
                print(f"[{k + 1}/{len(cells)}] {n1}={labels1[i]} {n2}={labels2[j]}{seed_note}: "
                      f"{job.state}  rmse {run_row['rmse']:.5g}  {run_row['seconds']:.3g} s",
                      file=sys.stderr)

        points = {key: summarise(rs) for key, rs in runs.items()}
        order = [(i, j) for i in range(len(values1)) for j in range(len(values2))]
        with open(out_dir / "sweep.csv", "w", newline="") as f:
            w = csv.writer(f)
            if seeds == 1:
                w.writerow([n1, n2, "algorithm", "rmse", "relmse", "seconds", "job", "state"])
                for i, j in order:
                    r = runs[(i, j)][0]
                    w.writerow([labels1[i], labels2[j], algorithm, fmt(r["rmse"]),
                                fmt(r["relmse"]), fmt(r["seconds"], 6), r["job"], r["state"]])
            else:
                w.writerow([n1, n2, "algorithm", "seeds", "rmse", "rmse_std", "rmse_se",
                            "relmse", "relmse_std", "relmse_se", "seconds", "jobs", "state"])
                for i, j in order:
                    p = points[(i, j)]
                    w.writerow([labels1[i], labels2[j], algorithm, seeds, fmt(p["rmse"]),
                                fmt(p["rmse_std"]), fmt(p["rmse_se"]), fmt(p["relmse"]),
                                fmt(p["relmse_std"]), fmt(p["relmse_se"]), fmt(p["seconds"], 6),
                                " ".join(r["job"] for r in runs[(i, j)]), p["state"]])
        if seeds > 1:
            with open(out_dir / "runs.csv", "w", newline="") as f:
                w = csv.writer(f)
                w.writerow([n1, n2, "seed", "rmse", "relmse", "seconds", "job", "state"])
                for i, j in order:
                    for r in runs[(i, j)]:
                        w.writerow([labels1[i], labels2[j], r["seed"], fmt(r["rmse"]),
                                    fmt(r["relmse"]), fmt(r["seconds"], 6), r["job"], r["state"]])
        make_figures(out_dir, points, (n1, labels1, values1), (n2, labels2, values2), images,
                     reference, seeds)
        failed = [r for rs in runs.values() for r in rs if r["state"] != "done"]
        if failed:
            raise PartitaError(f"{len(failed)} of {len(cells)} jobs did not finish "
                               f"(job {failed[0]['job']} {failed[0]['state']})")
        if not args.quiet:
            extra = f", {out_dir / 'runs.csv'}" if seeds > 1 else ""
            print(f"wrote {out_dir / 'sweep.csv'}{extra}, {out_dir / 'grid.png'}, "
                  f"{out_dir / 'rmse.png'}", file=sys.stderr)
        client.close()
    finally:
        if daemon:
            daemon.stop()
    return 0


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog=__doc__.split("\n", 2)[2])
    p.add_argument("scene")
    p.add_argument("--server", help="HOST:PORT (default: a private partitad)")
    p.add_argument("--token-file")
    p.add_argument("--tls-ca")
    p.add_argument("--param1", default=DEFAULT_ROWS, help="rows: NAME=V1,V2,...")
    p.add_argument("--param2", default=DEFAULT_COLUMNS, help="columns: NAME=V1,V2,...")
    p.add_argument("--seeds", type=int, default=1,
                   help="renders per grid point (seeds S..S+N-1, S = --set seed or 1)")
    p.add_argument("--algorithm", help="default: guided if offered, else pt")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="a parameter fixed for every job (repeatable)")
    p.add_argument("--reference", help="reference EXR")
    p.add_argument("--reference-spp", type=int, help="render a reference with N spp first")
    p.add_argument("--reference-algorithm", default="pt", choices=("pt", "bdpt"),
                   help="the algorithm of --reference-spp's reference (default pt)")
    p.add_argument("--out-dir")
    p.add_argument("--label", help="job label (default: sweep.py:<scene>)")
    p.add_argument("--threads", type=int, help="threads of a private partitad")
    p.add_argument("-q", "--quiet", action="store_true")
    args = p.parse_args(argv)
    try:
        return run(args)
    except KeyboardInterrupt:
        print("sweep.py: error: interrupted", file=sys.stderr)
        return 130
    except Exception as e:  # one line, whatever went wrong
        print(f"sweep.py: error: {' '.join(str(e).split())}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
