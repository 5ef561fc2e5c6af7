#!/usr/bin/python3
"""Render a grid over two job parameters and measure each image against a reference.

    sweep.py SCENE [--server HOST:PORT] [--param1 y=8,32,128] [--param2 radius=5,10,20]
             [--algorithm A] [--set NAME=VALUE ...] (--reference REF.exr | --reference-spp N)
             [--out-dir DIR]

SCENE is a .gltf/.glb file (uploaded) or a scene name of the server's scene root. The
parameters are job parameters: y, radius, k, epsilon, spp, mpp, seconds, max-depth, seed, width,
height (the defaults, |Y'| x R, are the paper's Figure 8 study). --set fixes others for every
job (e.g. --set mpp=32 --set width=160). Without --algorithm it renders with "guided" when the
server offers it, else "pt". A parameter the algorithm ignores (the server says which it
reads) is refused, since every image would be the same: with "pt", sweep e.g. spp and
max-depth; |Y'| x R needs the guided method.

The reference is --reference REF.exr, or with --reference-spp N a path-traced ("pt", N spp)
render of the same scene, resolution and depth made first (saved as DIR/reference.exr).

Writes into DIR (default sweep-<scene>):
  sweep.csv    one row per grid point: the two parameters, algorithm, rmse, relmse, seconds, job
  grid.png     the images, rows = param1, columns = param2, RMSE under each (like Figure 8)
  rmse.png     RMSE against param2 (a curve per param1 value) and against render seconds
  renders/     each result's EXR, PNG and JSON metadata
Without --server it starts a private partitad for the duration (partita_client.LocalDaemon).
Exit status 0 on success, else one line "sweep.py: error: ..." on stderr.
"""

from __future__ import annotations

import argparse
import csv
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import numpy as np  # noqa: E402

PARAMS = {"y": int, "radius": float, "k": int, "epsilon": float, "spp": float, "mpp": float,
          "seconds": float, "max-depth": int, "seed": int, "width": int, "height": int}
BUDGETS = ("spp", "mpp", "seconds")


class UsageError(Exception):
    pass


def parse_value(name: str, text: str):
    kind = PARAMS[name]
    try:
        v = kind(text)
    except ValueError:
        raise UsageError(f"{name}={text}: not {'a whole number' if kind is int else 'a number'}")
    return v


def parse_axis(text: str):
    name, eq, values = text.partition("=")
    name = name.replace("_", "-")
    if not eq or name not in PARAMS:
        raise UsageError(f"bad parameter '{text}': expected NAME=V1,V2,... with NAME one of "
                         f"{', '.join(PARAMS)}")
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


def make_figures(out_dir: Path, rows, a1, a2, images, reference):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

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
            r = rows[i * len(labels2) + j]
            ax.set_xlabel(f"RMSE {r['rmse']:.4g}" if r["rmse"] == r["rmse"] else r["state"],
                          fontsize=8)
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
        pts = [(values2[j], rows[i * len(labels2) + j]) for j in range(len(labels2))]
        pts = [(x, r) for x, r in pts if r["rmse"] == r["rmse"]]
        if not pts:
            continue
        left.plot([x for x, _ in pts], [r["rmse"] for _, r in pts], "o-", label=f"{n1}={l1}")
        right.plot([r["seconds"] for _, r in pts], [r["rmse"] for _, r in pts], "o-",
                   label=f"{n1}={l1}")
    left.set_xlabel(n2)
    left.set_ylabel("RMSE")
    left.set_title(f"RMSE against {n2}")
    right.set_xlabel("render seconds")
    right.set_ylabel("RMSE")
    right.set_title("RMSE against time")
    for ax in (left, right):
        if any(r["rmse"] > 0 for r in rows if r["rmse"] == r["rmse"]):
            ax.set_yscale("log")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out_dir / "rmse.png", dpi=100)
    plt.close(fig)


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
        if not eq or name not in PARAMS:
            raise UsageError(f"bad --set '{s}': expected NAME=VALUE with NAME one of "
                             f"{', '.join(PARAMS)}")
        fixed[name] = parse_value(name, value)
    if sum(n in BUDGETS for n in {n1, n2, *fixed}) > 1:
        raise UsageError("spp, mpp and seconds all set the budget: give only one of them")
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

    daemon = None
    if not args.server:
        daemon = LocalDaemon(threads=args.threads)
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
        for flag, name in (("--param1", n1), ("--param2", n2)):
            if reads and name not in reads:
                raise UsageError(f"{flag} {name}: algorithm '{algorithm}' ignores {name}, so "
                                 f"every image would be the same ({algorithm} reads "
                                 f"{', '.join(reads)})")
        label = args.label or f"sweep.py:{stem}"
        base = {kwargs_name(k): v for k, v in fixed.items()}

        if reference is None:
            ref_params = {k: v for k, v in base.items() if k in ("width", "height", "max_depth")}
            ref_id = client.submit(args.scene, algorithm="pt", spp=args.reference_spp,
                                   seed=987654321, label=label + ":reference", **ref_params)
            reference = client.result(ref_id)["combined"]
            client.download(ref_id, out_dir / "reference.exr")

        cells = []
        for i, v1 in enumerate(values1):
            for j, v2 in enumerate(values2):
                params = dict(base)
                for n in (n1, n2):
                    if n in BUDGETS:
                        for b in BUDGETS:
                            params.pop(b, None)
                params[kwargs_name(n1)] = v1
                params[kwargs_name(n2)] = v2
                job_id = client.submit(args.scene, algorithm=algorithm, label=label, **params)
                cells.append((i, j, job_id))

        rows, images = [], {}
        for k, (i, j, job_id) in enumerate(cells):
            job = client.wait(job_id)
            row = {n1: labels1[i], n2: labels2[j], "algorithm": algorithm, "rmse": float("nan"),
                   "relmse": float("nan"), "seconds": job.seconds if job.seconds is not None
                   else float("nan"), "job": job_id, "state": job.state}
            if job.state == "done":
                combined = client.result(job_id, wait=False)["combined"]
                images[(i, j)] = combined
                client.download(job_id, out_dir / "renders" / f"{n1}={labels1[i]}_{n2}={labels2[j]}.exr")
                if combined.shape == reference.shape:
                    row["rmse"] = rmse(combined, reference)
                    row["relmse"] = rel_mse(combined, reference)
            rows.append(row)
            if not args.quiet:
                print(f"[{k + 1}/{len(cells)}] {n1}={labels1[i]} {n2}={labels2[j]}: {job.state}"
                      f"  rmse {row['rmse']:.5g}  {row['seconds']:.3g} s", file=sys.stderr)

        with open(out_dir / "sweep.csv", "w", newline="") as f:
            w = csv.writer(f)
            w.writerow([n1, n2, "algorithm", "rmse", "relmse", "seconds", "job", "state"])
            for r in rows:
                w.writerow([r[n1], r[n2], r["algorithm"], f"{r['rmse']:.8g}",
                            f"{r['relmse']:.8g}", f"{r['seconds']:.6g}", r["job"], r["state"]])
        make_figures(out_dir, rows, (n1, labels1, values1), (n2, labels2, values2), images,
                     reference)
        failed = [r for r in rows if r["state"] != "done"]
        if failed:
            raise PartitaError(f"{len(failed)} of {len(rows)} jobs did not finish "
                               f"(job {failed[0]['job']} {failed[0]['state']})")
        if not args.quiet:
            print(f"wrote {out_dir / 'sweep.csv'}, {out_dir / 'grid.png'}, {out_dir / 'rmse.png'}",
                  file=sys.stderr)
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
    p.add_argument("--param1", default="y=8,32,128", help="rows: NAME=V1,V2,...")
    p.add_argument("--param2", default="radius=5,10,20", help="columns: NAME=V1,V2,...")
    p.add_argument("--algorithm", help="default: guided if offered, else pt")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="a parameter fixed for every job (repeatable)")
    p.add_argument("--reference", help="reference EXR")
    p.add_argument("--reference-spp", type=int, help="render a pt reference with N spp first")
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
