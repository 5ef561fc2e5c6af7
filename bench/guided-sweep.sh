#!/bin/sh
# guided: the |Y'| x R study (issue #13 item 6, the paper's Figure 8) and the epsilon sweep that
# chose guided's defaults of radius and epsilon (GuidedSettings; docs/guided-sweep.md). Everything renders
# through a private partitad started by client/python/sweep.py (one job at a time); the
# references are BDPT renders by `partita-eval reference` from the shared cache
# (build-bench/references/, as partitioned-study.sh makes them).
#   1. per scene at 128x96, 32 mpp: the grid rows R = 2,5,10,20,40, columns |Y'| = 8,32,128,512,
#      SEEDS seeds (default 4; seeds 1..SEEDS);
#   2. the column |Y'| = 128 again for R = 5,10,20,40 with MORE_SEEDS more seeds (default 8;
#      seeds SEEDS+1..): the candidates for the default with 12 seeds;
#   3. epsilon = 0.001,0.01,0.1,0.5 at R = EPS_RADIUS (default 10: the default R when the study
#      ran, and R = 10 and 20 tie at 128x96), |Y'| = 128, 8 seeds;
#   4. per scene at 256x192 (a 512-spp BDPT reference with 64 type layers), R = 5,10,20,40 (and
#      80 on bathroom) at |Y'| = 128, 4 seeds: whether the good R scales with the image size;
# then bench/guided-sweep-shape-error.py on every run (the error with the pre-pass's b_i taken
# out) and bench/guided-sweep-table.py prints docs/guided-sweep.md's tables.
# Needs build/ (partitad, the Python stubs) and build-bench/bench/partita-eval (PARTITA_EVAL=).
# Renders run under `nice -n 10` (NICE= to change). OUT defaults to build-bench/guided-sweep.
#   bench/guided-sweep.sh       (SCENES="cornell-glass bathroom", SEEDS=4, MORE_SEEDS=8)
set -eu
cd "$(dirname "$0")/.."
EVAL=${PARTITA_EVAL:-build-bench/bench/partita-eval}
NICE=${NICE-nice -n 10}
OUT=${OUT:-build-bench/guided-sweep}
SEEDS=${SEEDS:-4}
MORE_SEEDS=${MORE_SEEDS:-8}
EPS_RADIUS=${EPS_RADIUS:-10}
export PYTHONPATH=build/python:client/python MPLBACKEND=Agg
export PARTITA_PARTITAD=${PARTITA_PARTITAD:-build/server/partitad}
SWEEP="$NICE /usr/bin/python3 client/python/sweep.py"
mkdir -p "$OUT"

reference() {  # scene W H SPP LAYERS -> OUT/<scene>-WxH-ref.exr
    $NICE "$EVAL" reference --scene "scenes/$1/$1.gltf" --algorithm bdpt --spp "$4" \
        --width "$2" --height "$3" --layers "$5" --quiet --out "$OUT/$1-$2x$3-ref.exr"
}

for scene in ${SCENES:-cornell-glass bathroom}; do
    reference "$scene" 128 96 1024 1024
    ref="$OUT/$scene-128x96-ref.exr"
    common="--algorithm guided --set width=128 --set height=96 --set mpp=32 --reference $ref -q"
    $SWEEP "$scene" $common --seeds "$SEEDS" --out-dir "$OUT/$scene"
    $SWEEP "$scene" $common --param1 radius=5,10,20,40 --param2 y=128 --seeds "$MORE_SEEDS" \
        --set seed=$((SEEDS + 1)) --out-dir "$OUT/$scene-y128-more"
    $SWEEP "$scene" $common --param1 radius="$EPS_RADIUS" --param2 epsilon=0.001,0.01,0.1,0.5 \
        --set y=128 --seeds 8 --out-dir "$OUT/$scene-epsilon"
    for d in "$scene" "$scene-y128-more" "$scene-epsilon"; do
        $NICE /usr/bin/python3 bench/guided-sweep-shape-error.py "$OUT/$d" "$ref"
    done
done
for scene in ${SCENES:-cornell-glass bathroom}; do
    radii=5,10,20,40
    [ "$scene" = bathroom ] && radii=5,10,20,40,80
    reference "$scene" 256 192 512 64
    $SWEEP "$scene" --algorithm guided --set width=256 --set height=192 --set mpp=32 -q \
        --reference "$OUT/$scene-256x192-ref.exr" --param1 radius=$radii --param2 y=128 \
        --seeds 4 --out-dir "$OUT/$scene-256x192"
    $NICE /usr/bin/python3 bench/guided-sweep-shape-error.py "$OUT/$scene-256x192" \
        "$OUT/$scene-256x192-ref.exr"
done

for scene in ${SCENES:-cornell-glass bathroom}; do
    for runs in runs.csv runs-shape.csv; do
        echo "== $scene, $runs"
        bench/guided-sweep-table.py "$OUT/$scene" "$OUT/$scene-y128-more" --runs "$runs"
        bench/guided-sweep-table.py "$OUT/$scene-epsilon" --runs "$runs"
    done
done
for scene in ${SCENES:-cornell-glass bathroom}; do
    echo "== $scene 256x192"
    bench/guided-sweep-table.py "$OUT/$scene-256x192" --base radius=10,y=128 --long
done
