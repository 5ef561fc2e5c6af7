#!/bin/sh
# Issue #22's equal-time protocol: pt, bdpt and mlt on door-ajar, bathroom, pool, cornell-glass
# and cornell at 256x192, 3 seeds, 10 s and 40 s a render, against references of at least 16x
# the longest budget (pt: 19000-28000 spp, ~640 s on 2 threads each; their own error from their
# two halves travels with them, and quality prints it). The three algorithms of a scene run
# side by side in one process, so load from elsewhere hits them alike.
#   bench/mlt-equal-time.sh      (REFS=/tmp/refcache-256: REFS/<scene>-256.exr, made by
#                                 MAKE_REFS=1 or partita-eval reference --algorithm pt --spp N
#                                 --width 256 --height 192 --out REFS/<scene>-256.exr;
#                                 OUT=build-bench/mlt-equal-time, BUDGETS="10 40", SEEDS=3)
# JSON in OUT/<scene>-<budget>s.json; bench/mlt-study-table.py OUT/*.json prints the tables.
set -eu
cd "$(dirname "$0")/.."
EVAL=${PARTITA_EVAL:-build-bench/bench/partita-eval}
REFS=${REFS:-/tmp/refcache-256}
OUT=${OUT:-build-bench/mlt-equal-time}
mkdir -p "$OUT" "$REFS"
reference_spp() {  # ~640 s of pt on 2 threads of this machine (2026-12-06)
    case $1 in bathroom) echo 21000 ;; pool) echo 19000 ;; cornell-glass) echo 26000 ;; *) echo 28000 ;; esac
}
failed=
for scene in ${SCENES:-door-ajar bathroom pool cornell-glass cornell}; do
    gltf=scenes/$scene/$scene.gltf
    ref=$REFS/$scene-256.exr
    if [ ! -f "$ref" ] && [ -n "${MAKE_REFS:-}" ]; then
        "$EVAL" reference --scene "$gltf" --algorithm pt --spp "$(reference_spp "$scene")" \
            --width 256 --height 192 --quiet --out "$ref"
    fi
    for budget in ${BUDGETS:-10 40}; do
        "$EVAL" quality --scene "$gltf" --reference "$ref" --algorithms pt,bdpt,mlt \
            --seconds "$budget" --seeds "${SEEDS:-3}" --quiet --json "$OUT/$scene-${budget}s.json" \
            >"$OUT/$scene-${budget}s.txt" || failed="$failed $scene:$budget"
    done
done
[ -z "$failed" ] || { echo "mlt-equal-time: quality failed for:$failed" >&2; exit 1; }
