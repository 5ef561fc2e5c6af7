#!/bin/sh
# The CPU cost of one mutation of mlt, partitioned and guided, by difference (issue #13 item 4,
# a cross-check of `quality`'s sampling-cost table, which divides wall render_seconds, burn-in
# included, by the counted mutations and so moves with the load of a shared machine). Per
# scene and algorithm, partita-local renders seed 1 on THREADS threads (default 1) at LOW and
# at HIGH mutations per pixel (defaults 8 and 72) under /usr/bin/time: everything before the
# chains (scene, start-up, guides, burn-in) and the first LOW mpp are the same in both renders
# of a seed, so (CPU seconds at HIGH - at LOW) / ((HIGH - LOW) x pixels) is the CPU time of one
# mutation (user + system; the process's CPU, so other processes' load changes it less than a
# wall clock, though a busy sibling core still slows it). REPEATS rounds (default 2), each
# visiting every scene and algorithm, so that load comes and goes alike for all. One line per
# render in OUT/cost.tsv (round, scene, algorithm, mpp, user, sys, wall, and from the EXR's
# statistics render_seconds and the mutations proposed, burn-in included);
# bench/guided-study-table.py cost prints the table.
#   bench/guided-cost.sh   (SIZE=128x96, LOW=8, HIGH=72, THREADS=1, REPEATS=2, SCENES=...,
#                           ALGORITHMS="mlt partitioned guided")
set -eu
cd "$(dirname "$0")/.."
LOCAL=${PARTITA_LOCAL:-build-bench/tools/local/partita-local}
SIZE=${SIZE:-128x96}
LOW=${LOW:-8}
HIGH=${HIGH:-72}
NICE=${NICE-nice -n 10}
OUT=${OUT:-build-bench/guided-cost}
mkdir -p "$OUT"
tsv=$OUT/cost.tsv
printf 'round\tscene\talgorithm\tmpp\tuser\tsys\twall\trender_seconds\tproposed\tmutations\twidth\theight\n' >"$tsv"
failed=
round=1
while [ "$round" -le "${REPEATS:-2}" ]; do
    for scene in ${SCENES:-cornell cornell-glass cornell-point door-ajar bathroom pool}; do
        for a in ${ALGORITHMS:-mlt partitioned guided}; do
            for mpp in "$LOW" "$HIGH"; do
                exr=$OUT/render.exr
                if ! $NICE /usr/bin/time -f '%U %S %e' -o "$OUT/time.txt" "$LOCAL" render \
                    "scenes/$scene/$scene.gltf" --algorithm "$a" --mpp "$mpp" --seed 1 \
                    --width "${SIZE%x*}" --height "${SIZE#*x}" --threads "${THREADS:-1}" --quiet \
                    --out "$exr" >/dev/null 2>"$OUT/stderr.txt"; then
                    failed="$failed $scene:$a:$mpp"
                    continue
                fi
                stats=$(iinfo -v "$exr" | sed -n 's/^ *partita:stat:\([a-z_]*\): "\(.*\)"$/\1=\2/p')
                python3 - "$round" "$scene" "$a" "$mpp" "$(cat "$OUT/time.txt")" "$SIZE" "$stats" \
                    >>"$tsv" <<'EOF'
import sys
rnd, scene, a, mpp, times, size, stats = sys.argv[1:]
s = dict(l.split("=", 1) for l in stats.split("\n") if "=" in l)
proposed = sum(float(v) for k, v in s.items() if k.startswith("proposed_"))
w, h = size.split("x")
print("\t".join([rnd, scene, a, mpp, *times.split(), s.get("render_seconds", ""), f"{proposed:.0f}",
                 s.get("mutations", ""), w, h]))
EOF
                rm -f "$exr" "${exr%.exr}.png"
            done
        done
    done
    round=$((round + 1))
done
cat "$tsv"
[ -z "$failed" ] || { echo "guided-cost: failed:$failed" >&2; exit 1; }
