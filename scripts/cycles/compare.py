#!/usr/bin/python3
"""Block-wise statistical comparison of Partita renders with Cycles references.

    /usr/bin/python3 scripts/cycles/compare.py --partita p1.exr p2.exr ... \
        --cycles c1.exr c2.exr ... [--block 8] [--alpha 0.01] [--json out.json]

Inputs: several Partita EXRs of the same job with independent --seed (combined layer: channels
R,G,B; the per-path-type layers are ignored) and several Cycles EXRs from render_cycles.py with
independent seeds, each with its raw supersampled render next to it (<name>.raw.exr).

For every block of B x B pixels and every channel the test compares the mean over seeds of the
block average in both renderers:

    z = (mean_P - mean_C) / sqrt(se_P^2 + se_C^2)

The standard errors come from the seeds alone, nothing is tuned by hand. Within one render the
estimates of different pixels (Partita: each pixel sample has its own random stream) and of
different Cycles cells (box filter, one cell per Cycles pixel) are independent, so the variance
of a block average is sum_i a_i^2 var_i / n_seeds, with var_i each pixel's (cell's) sample
variance over the seeds and a_i its weight in the block average (Partita: 1/B^2; Cycles: the
tent-reconstruction weight of the cell, summed over the block's pixels, as render_cycles.py
builds the W x H image). This has far more degrees of freedom than the variance of B^2-pixel
means over a handful of seeds; the Welch-Satterthwaite degrees of freedom are computed per block
and the test uses Student-t with them. The independence assumption is checked, not trusted: the
report gives, per renderer, the ratio of the seed-to-seed variance of block means to the pooled
estimate (about 1 when it holds) and the standard deviation of all z (about 1 when the noise
model is right and the renderers agree).

Pass: every |z| below the Sidak-corrected two-sided threshold for a family-wise alpha (default
0.01) over all blocks x channels. Blocks whose pixels have zero variance in both renderers (an
emitter seen directly, filling the block) are compared for equality up to float rounding
(relative 1e-5) instead. Also reported: the relative difference of the whole-image mean, with
its own z.
"""
import argparse
import json
import math
import sys

import numpy as np
import OpenImageIO as oiio
from scipy import stats


def read_rgb(path):
    inp = oiio.ImageInput.open(path)
    if inp is None:
        sys.exit("compare.py: cannot read %s: %s" % (path, oiio.geterror()))
    spec = inp.spec()
    data = inp.read_image(oiio.FLOAT)
    names = list(spec.channelnames)
    meta = {a.name: a.value for a in spec.extra_attribs}
    inp.close()
    try:
        rgb = np.stack([data[:, :, names.index(c)] for c in "RGB"], axis=-1)
    except ValueError:
        sys.exit("compare.py: %s has no R,G,B channels (has %s)" % (path, names[:6]))
    return rgb.astype(np.float64), meta


def tent_cell_weights(k):
    def cdf(u):
        return 0.5 * (1 + u) ** 2 if u <= 0 else 1 - 0.5 * (1 - u) ** 2
    edges = [-1 + j / k for j in range(2 * k + 1)]
    return np.array([cdf(edges[j + 1]) - cdf(edges[j]) for j in range(2 * k)])


def block_cell_weights(n_pixels, block, k):
    """(n_blocks, (n_pixels + 2) k): weight of each raw cell (1 px overscan) in each block's
    average along one axis; render_cycles.py's tent reconstruction, averaged over the block."""
    w = tent_cell_weights(k)
    out = np.zeros((n_pixels // block, (n_pixels + 2) * k))
    for b in range(n_pixels // block):
        for x in range(b * block, (b + 1) * block):
            start = x * k + k // 2  # pixel x covers cells (x + 0.5) k ... (x + 2.5) k - 1
            out[b, start:start + 2 * k] += w / block
    return out


def block_means(img, block):
    h, w, c = img.shape
    return img.reshape(h // block, block, w // block, block, c).mean(axis=(1, 3))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--partita", nargs="+", required=True, help="Partita EXRs, one per seed")
    ap.add_argument("--cycles", nargs="+", required=True, help="render_cycles.py EXRs, one per seed")
    ap.add_argument("--block", type=int, default=8)
    ap.add_argument("--alpha", type=float, default=0.01, help="family-wise significance level")
    ap.add_argument("--json", help="write the numbers here too")
    a = ap.parse_args()
    nP, nC, B = len(a.partita), len(a.cycles), a.block
    if nP < 2 or nC < 2:
        sys.exit("compare.py: need at least 2 seeds per renderer for a variance estimate")

    P = np.stack([read_rgb(p)[0] for p in a.partita])  # (nP, H, W, 3)
    C, raws, ks = [], [], set()
    for p in a.cycles:
        img, meta = read_rgb(p)
        raw_path = (p[:-4] if p.endswith(".exr") else p) + ".raw.exr"
        raw, rmeta = read_rgb(raw_path)
        ks.add(int(rmeta.get("cycles:supersample", meta.get("cycles:supersample", 0))))
        C.append(img)
        raws.append(raw)
    C, R = np.stack(C), np.stack(raws)
    if len(ks) != 1 or 0 in ks:
        sys.exit("compare.py: Cycles EXRs lack (or disagree on) cycles:supersample")
    k = ks.pop()
    _, H, W, _ = P.shape
    if C.shape[1:] != P.shape[1:]:
        sys.exit("compare.py: image sizes differ: Partita %s, Cycles %s" % (P.shape[1:3], C.shape[1:3]))
    if H % B or W % B:
        sys.exit("compare.py: %dx%d is not a multiple of the block size %d" % (W, H, B))
    if R.shape[1:3] != ((H + 2) * k, (W + 2) * k):
        sys.exit("compare.py: raw Cycles render has the wrong size %s" % (R.shape[1:3],))

    # Block means per seed, and their mean over seeds.
    bP = np.stack([block_means(x, B) for x in P])  # (nP, by, bx, 3)
    bC = np.stack([block_means(x, B) for x in C])
    mP, mC = bP.mean(0), bC.mean(0)

    # Pooled variance of the seed-mean block averages, with Welch-Satterthwaite df.
    vpx = P.var(axis=0, ddof=1)  # per pixel, over seeds
    a2 = (1.0 / (B * B)) ** 2
    varP = block_means(vpx, B) * (B * B) * a2 / nP
    dfP_den = block_means(vpx ** 2, B) * (B * B) * (a2 / nP) ** 2 / (nP - 1)
    vcell = R.var(axis=0, ddof=1)  # per raw cell, over seeds
    WY, WX = block_cell_weights(H, B, k), block_cell_weights(W, B, k)
    varC = np.einsum("iy,yxc,jx->ijc", WY ** 2, vcell, WX ** 2) / nC
    dfC_den = np.einsum("iy,yxc,jx->ijc", WY ** 4, vcell ** 2, WX ** 4) / nC ** 2 / (nC - 1)
    # Consistency of the W x H Cycles image with its raw cells (same linear map).
    mC_raw = np.einsum("iy,syxc,jx->sijc", WY, R, WX).mean(0)
    recon_err = float(np.max(np.abs(mC_raw - mC) / np.maximum(np.abs(mC), 1e-6)))

    var = varP + varC
    df = np.where(var > 0, var ** 2 / np.maximum(
        np.where(varP > 0, dfP_den, 0) + np.where(varC > 0, dfC_den, 0), 1e-300), np.inf)
    diff = mP - mC
    deterministic = var == 0
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.where(deterministic, 0.0, diff / np.sqrt(var))
    M = int((~deterministic).sum())
    alpha_each = 1 - (1 - a.alpha) ** (1 / M)  # Sidak
    thr = stats.t.ppf(1 - alpha_each / 2, df)  # per test, from its own df
    pvals = 2 * stats.t.sf(np.abs(z), df)
    stoch_fail = (~deterministic) & (pvals < alpha_each)
    det_fail = deterministic & (np.abs(diff) > 1e-5 * np.maximum(np.abs(mC), 1e-6))
    zs = z[~deterministic]

    # Noise-model checks: seed-to-seed variance of block means vs the pooled estimate.
    def ratio(bx, v, n):
        direct = bx.var(axis=0, ddof=1) / n
        ok = v > 0
        return float(np.median(direct[ok] / v[ok])), float(np.mean(direct[ok]) / np.mean(v[ok]))

    rP, rC = ratio(bP, varP, nP), ratio(bC, varC, nC)

    # Whole image.
    imP, imC = P.mean(axis=(0, 1, 2)), C.mean(axis=(0, 1, 2))  # per channel
    nb = (H // B) * (W // B)
    vim = (varP.sum(axis=(0, 1)) + varC.sum(axis=(0, 1))) / nb ** 2
    rel = (imP - imC) / imC
    zim = (imP - imC) / np.sqrt(vim)
    lum = np.array([0.2126, 0.7152, 0.0722])
    rel_lum = float((imP @ lum - imC @ lum) / (imC @ lum))
    z_lum = float((imP @ lum - imC @ lum) / math.sqrt(vim @ lum ** 2))

    worst = np.unravel_index(np.argmax(np.abs(z)), z.shape)
    passed = not stoch_fail.any() and not det_fail.any()
    res = {
        "image": [W, H], "block": B, "seeds_partita": nP, "seeds_cycles": nC, "supersample": k,
        "tests": int(z.size), "stochastic_tests": M, "deterministic_tests": int(deterministic.sum()),
        "alpha_familywise": a.alpha, "alpha_per_test_sidak": alpha_each,
        "threshold_abs_z_min": float(np.min(thr[~deterministic])),
        "threshold_abs_z_median": float(np.median(thr[~deterministic])),
        "df_min": float(np.min(df[~deterministic])), "df_median": float(np.median(df[~deterministic])),
        "max_abs_z": float(np.max(np.abs(zs))), "mean_z": float(zs.mean()), "std_z": float(zs.std()),
        "frac_abs_z_gt_2": float(np.mean(np.abs(zs) > 2)), "frac_abs_z_gt_3": float(np.mean(np.abs(zs) > 3)),
        "min_p": float(np.min(pvals[~deterministic])),
        "worst_block": {"bx": int(worst[1]), "by": int(worst[0]), "channel": "RGB"[worst[2]],
                        "z": float(z[worst]), "partita": float(mP[worst]), "cycles": float(mC[worst]),
                        "se": float(math.sqrt(var[worst]))},
        "failing_stochastic": int(stoch_fail.sum()), "failing_deterministic": int(det_fail.sum()),
        "var_ratio_direct_over_pooled_partita(median,mean)": rP,
        "var_ratio_direct_over_pooled_cycles(median,mean)": rC,
        "cycles_reconstruction_rel_err": recon_err,
        "image_mean_partita": imP.tolist(), "image_mean_cycles": imC.tolist(),
        "image_mean_rel_diff": rel.tolist(), "image_mean_z": zim.tolist(),
        "image_mean_rel_diff_luminance": rel_lum, "image_mean_z_luminance": z_lum,
        "pass": passed,
    }

    print("Partita vs Cycles: %dx%d, %dx%d blocks, %d Partita seeds, %d Cycles seeds (k=%d)"
          % (W, H, B, B, nP, nC, k))
    print("block tests: %d (%d stochastic, %d deterministic = emitter filling the block)"
          % (z.size, M, int(deterministic.sum())))
    print("Sidak: family-wise alpha %g -> per-test alpha %.3g; |z| threshold (Student-t, "
          "per-block Welch df; median df %.0f, min df %.0f): median %.3f, min %.3f"
          % (a.alpha, alpha_each, res["df_median"], res["df_min"],
             res["threshold_abs_z_median"], res["threshold_abs_z_min"]))
    print("z: max |z| %.3f, mean %+.3f, std %.3f, |z|>2: %.1f%%, |z|>3: %.1f%% (normal: 4.6%%, 0.27%%)"
          % (res["max_abs_z"], res["mean_z"], res["std_z"], 100 * res["frac_abs_z_gt_2"],
             100 * res["frac_abs_z_gt_3"]))
    wb = res["worst_block"]
    print("worst block (%d,%d) %s: Partita %.6g, Cycles %.6g, se %.3g, z %+.3f, p %.3g"
          % (wb["bx"], wb["by"], wb["channel"], wb["partita"], wb["cycles"], wb["se"], wb["z"],
             res["min_p"]))
    print("noise model: seed-to-seed var of block means / pooled estimate (median, mean): "
          "Partita %.3f, %.3f; Cycles %.3f, %.3f" % (*rP, *rC))
    print("whole-image mean R,G,B: Partita %s  Cycles %s" %
          (" ".join("%.6f" % v for v in imP), " ".join("%.6f" % v for v in imC)))
    print("whole-image relative difference (Partita - Cycles)/Cycles: R %+.4f%% G %+.4f%% B %+.4f%% "
          "(z %+.2f %+.2f %+.2f); luminance %+.4f%% (z %+.2f)"
          % (*(100 * rel), *zim, 100 * rel_lum, z_lum))
    print("failing blocks: %d stochastic, %d deterministic -> %s"
          % (res["failing_stochastic"], res["failing_deterministic"], "PASS" if passed else "FAIL"))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(res, f, indent=2)
    return 0 if passed else 1


if __name__ == "__main__":
    sys.exit(main())
