#!/usr/bin/env python3
"""What one mlt mutation costs in path-tracer samples (issue #22 item 4; target <= 0.7).

Per scene and round, partita-local renders pt at SPP samples per pixel and then mlt with
--direct chains (the chains do all the work) at MPP mutations per pixel, one right after the
other on THREADS threads, and reads each render's statistics from its EXR:

    cost of a mutation in pt samples = (mlt render_seconds / mutations)
                                       / (pt render_seconds / (spp x pixels))

render_seconds is the sampling time: pt's passes, mlt's chains without its bootstrap. Pairing
pt and mlt within a round keeps a shared machine's load drifts out of most of the ratio; the
table gives the median over rounds with the spread.

    bench/mutation-cost.py [--threads 1] [--rounds 3] [--size 256x192] [--spp 16] [--mpp 32]
                           [--scenes cornell cornell-glass ...] [--local PATH] [--baseline PATH]

With --baseline (another build's partita-local), each round also renders mlt with it right
after the first, and the table adds its cost per mutation and the ratio of the two, pair by
pair, and a line with the ratio of the best rounds.
"""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile

SCENES = ["cornell", "cornell-glass", "cornell-point", "door-ajar", "bathroom", "pool"]


def stats_of(exr):
    out = subprocess.run(["oiiotool", "--info", "-v", exr], check=True, capture_output=True,
                         text=True).stdout
    stats = {}
    for line in out.splitlines():
        line = line.strip()
        if line.startswith("partita:stat:"):
            name, value = line[len("partita:stat:"):].split(":", 1)
            try:
                stats[name] = float(value.strip().strip('"'))
            except ValueError:  # a statistic in words, such as direct: "chains"
                pass
    return stats


def render(args, scene, algorithm, budget, exr, local=None):
    width, height = args.size.split("x")
    command = [local or args.local, "render", f"scenes/{scene}/{scene}.gltf", "--algorithm", algorithm,
               "--width", width, "--height", height, "--threads", str(args.threads), "--quiet",
               "--preview-interval", "0", "--seed", "1", "--out", exr] + budget
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
    return stats_of(exr)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--local", default="build-bench/tools/local/partita-local")
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--size", default="256x192")
    parser.add_argument("--spp", type=float, default=16)
    parser.add_argument("--mpp", type=float, default=32)
    parser.add_argument("--scenes", nargs="+", default=SCENES)
    parser.add_argument("--baseline", help="another partita-local to compare mutations with")
    args = parser.parse_args()
    os.chdir(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    width, height = (int(v) for v in args.size.split("x"))
    pixels = width * height
    rows = {scene: [] for scene in args.scenes}
    with tempfile.TemporaryDirectory() as folder:
        exr = os.path.join(folder, "render.exr")
        for _ in range(args.rounds):
            for scene in args.scenes:
                pt = render(args, scene, "pt", ["--spp", str(args.spp)], exr)
                mlt_budget = ["--mpp", str(args.mpp), "--param", "direct=chains"]
                mlt = render(args, scene, "mlt", mlt_budget, exr)
                pt_sample = pt["render_seconds"] / (args.spp * pixels)
                mutation = mlt["render_seconds"] / mlt["mutations"]
                row = [mutation / pt_sample, 1e9 * mutation, 1e9 * pt_sample]
                if args.baseline:
                    base = render(args, scene, "mlt", mlt_budget, exr, args.baseline)
                    row.append(1e9 * base["render_seconds"] / base["mutations"])
                rows[scene].append(row)
    print(f"threads {args.threads}, {args.size}, pt {args.spp:g} spp, mlt {args.mpp:g} mpp "
          f"(direct=chains), {args.rounds} rounds; median [min, max]")
    columns = ["mutation / pt sample", "ns per mutation", "ns per pt sample"]
    if args.baseline:
        columns.append("baseline's ns per mutation")
        for values in rows.values():
            for row in values:
                row.append(row[1] / row[3])
        columns.append("mutation / baseline's")
    print("| scene | " + " | ".join(columns) + " |")
    print("|---" * (len(columns) + 1) + "|")
    for scene, values in rows.items():
        cells = []
        for column in range(len(columns)):
            v = [row[column] for row in values]
            fmt = "{:.0f}" if column in (1, 2, 3) else "{:.2f}"
            cells.append(f"{fmt.format(statistics.median(v))} "
                         f"[{fmt.format(min(v))}, {fmt.format(max(v))}]")
        print(f"| {scene} | " + " | ".join(cells) + " |")
    if args.baseline:
        # On a machine whose speed drifts, the fastest run of each is the least disturbed.
        print("best of rounds, mutation / baseline's: " + ", ".join(
            f"{scene} {min(r[1] for r in v) / min(r[3] for r in v):.2f}"
            for scene, v in rows.items()))


if __name__ == "__main__":
    sys.exit(main())
