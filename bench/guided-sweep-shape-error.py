#!/usr/bin/env python3
"""The error of a guided (or partitioned) sweep's renders with the pre-pass's b_i taken out:
    bench/guided-sweep-shape-error.py DIR REF.exr       (DIR: a sweep.py --seeds N > 1 output)

A partition's image is b_i times its chains' histogram, so an error of the pre-pass's b_i
scales the whole layer, and the same error at every grid point (the pre-pass does not depend on
|Y'|, R or epsilon): at 32 mpp it dominates the combined RMSE and hides what the chains' moves
change (docs/partitioned-study.md, issue #12). Here each partition layer of a render (sweep.py keeps them
in DIR/renders/*.exr, one per partition: its type, or `complement`) is rescaled so that its mean
luminance is the reference's for the same paths (the layer of that type in REF, which must have
every type layer, as `partita-eval reference --layers 1024` makes; for the complement the
reference's combined image minus its layers of the K types), the rescaled layers are summed and
compared with REF's combined image. What remains is the error of where each partition's chains
put their energy, which is what |Y'|, R and epsilon act on.

Writes DIR/runs-shape.csv: runs.csv's columns with rmse and relmse replaced by these (read it
with bench/guided-sweep-table.py DIR --runs runs-shape.csv).
"""
import csv
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "client" / "python"))
from partita_client import read_exr, rel_mse, rmse  # noqa: E402

LUM = np.array([0.2126, 0.7152, 0.0722])


def mean_lum(img):
    return float((img.astype(np.float64) @ LUM).mean())


def shape_corrected(layers, ref):
    """The sum of the render's partition layers, each scaled to the reference's mean."""
    types = [n for n in layers if n not in ("combined", "complement")]
    total = np.zeros_like(ref["combined"], dtype=np.float64)
    for name, img in layers.items():
        if name == "combined":
            continue
        if name == "complement":
            target = ref["combined"].astype(np.float64) - sum(
                ref[t].astype(np.float64) for t in types if t in ref)
        else:
            target = ref.get(name)
            if target is None:  # a type the reference never sampled: no scale to match
                total += img
                continue
        m = mean_lum(img)
        total += img * (mean_lum(target) / m if m > 0 else 1.0)
    return total.astype(np.float32)


def main(argv):
    if len(argv) != 2:
        sys.exit(__doc__.split("\n")[1].strip())
    out_dir, ref_path = Path(argv[0]), argv[1]
    ref = read_exr(ref_path).layers()
    with open(out_dir / "runs.csv") as f:
        reader = csv.DictReader(f)
        fields = reader.fieldnames
        rows = list(reader)
    n1, n2 = fields[:2]
    for r in rows:
        if r["state"] != "done":
            continue
        exr = out_dir / "renders" / f"{n1}={r[n1]}_{n2}={r[n2]}_seed={r['seed']}.exr"
        img = shape_corrected(read_exr(exr).layers(), ref)
        r["rmse"] = f"{rmse(img, ref['combined']):.8g}"
        r["relmse"] = f"{rel_mse(img, ref['combined']):.8g}"
    with open(out_dir / "runs-shape.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields)
        w.writeheader()
        w.writerows(rows)
    print(f"wrote {out_dir / 'runs-shape.csv'}", file=sys.stderr)


if __name__ == "__main__":
    main(sys.argv[1:])
