#!/bin/sh
# guided against mlt and partitioned on every shipped scene (issue #13 item 7): a BDPT reference
# per scene with every type layer (the cache that make-references.sh and the other studies
# share), then
#  1. `quality --algorithms mlt,partitioned,guided --mpp MPP`: equal mutations per pixel, with the
#     same start-up budget for all three (--bootstrap BOOTSTRAP: mlt's BDPT bootstrap samples and
#     the partitioned methods' pre-pass samples are all the parameter `bootstrap`; the
#     pre-pass of partitioned and guided is BDPT, the default, so all three start from the same
#     estimator); mlt and partitioned are also measured on partitioned's partitions (guided's
#     are the same: same seed, same pre-pass);
#  2. `quality --algorithms pt,mlt,partitioned,guided --spp PT_SPP --equal-time`: mlt,
#     partitioned and guided get pt's mean wall time. Unless PT_SPP is given, it is chosen per
#     scene as in partitioned-study.sh, so that pt takes about the time mlt took for MPP
#     mutations per pixel in step 1: a one-seed pt render of CAL_SPP spp, times mlt's mean wall
#     time over pt's, rounded (at least 1). EQUAL_TIME_AT="mlt guided" also runs it at the time
#     guided took for MPP mpp (OUT/<scene>-equal-time-guided.*), and an entry A*F at F times
#     algorithm A's time (mlt*4: OUT/<scene>-equal-time-x4.*): the partitioned methods' fixed
#     start-up (pre-pass, guides, 1024 burn-in mutations per chain: 21 mpp at 128x96) is then a
#     smaller part of the budget.
# REF_SPP (default 1024) is the references' budget; REF_SPPS="pool=8192 bathroom=4096" gives
# some scenes more (a reference whose own error is close to the renders' compresses every ratio
# toward 1; the harness prints the reference's own RMSE, bench/guided-study-table.py subtracts
# it). SEEDS seeds each; the renders keep LAYERS type layers (default 64, so that mlt's and
# pt's films keep the K types apart from "other"). Every run's table goes to
# OUT/<scene>-<run>.txt (and stdout), its figures to OUT/<scene>-<run>.json;
# bench/guided-study-table.py turns those into docs/guided-study.md's tables. A scene that fails does
# not stop the others (the script exits 1 naming them at the end). Renders run under
# `nice -n 10` (NICE= to change); never run two studies at once. EQUAL_TIME=0 skips step 2;
# REUSE=1 keeps an existing step-1 JSON (and pt calibration) instead of rendering them again.
# ALGORITHMS (default mlt,partitioned,guided) are the MCMC methods compared; partitioned-study.sh
# runs this script with mlt,partitioned.
#   bench/guided-study.sh   (SIZE=128x96, REF_SPP=1024, MPP=32, BOOTSTRAP=100000, SEEDS=4;
#                            SCENES="cornell ..." picks scenes)
set -eu
cd "$(dirname "$0")/.."
EVAL=${PARTITA_EVAL:-build-bench/bench/partita-eval}
SIZE=${SIZE:-128x96}
W=${SIZE%x*}
H=${SIZE#*x}
MPP=${MPP:-32}
BOOTSTRAP=${BOOTSTRAP:-100000}
SEEDS=${SEEDS:-4}
CAL_SPP=${CAL_SPP:-64}
LAYERS=${LAYERS:-64}
NICE=${NICE-nice -n 10}
ALGORITHMS=${ALGORITHMS:-mlt,partitioned,guided}
OUT=${OUT:-build-bench/guided-study}
mkdir -p "$OUT"
failed=

# quality NAME SCENE ARGS...: one `quality` run, its table to OUT/SCENE-NAME.txt and stdout.
quality() {
    name=$1
    scene=$2
    shift 2
    echo "== $scene $name ($(date +%H:%M:%S))" >&2
    if $NICE "$EVAL" quality --scene "scenes/$scene/$scene.gltf" --reference "$OUT/$scene-ref.exr" \
        --bootstrap "$BOOTSTRAP" --layers "$LAYERS" --quiet --json "$OUT/$scene-$name.json" "$@" \
        >"$OUT/$scene-$name.txt"; then
        cat "$OUT/$scene-$name.txt"
    else
        failed="$failed $scene:$name"
        return 1
    fi
}

# json_field FILE ALGORITHM FIELD: a figure of one algorithm's result in a quality JSON file.
json_field() {
    python3 -c 'import json, sys
j = json.load(open(sys.argv[1]))
print(next(r[sys.argv[3]] for r in j["results"] if r["algorithm"] == sys.argv[2]))' "$@"
}

# ref_spp SCENE: the reference budget of SCENE (REF_SPPS entry, else REF_SPP).
ref_spp() {
    spp=${REF_SPP:-1024}
    for entry in ${REF_SPPS:-}; do
        [ "${entry%%=*}" != "$1" ] || spp=${entry#*=}
    done
    echo "$spp"
}

for scene in ${SCENES:-cornell cornell-glass cornell-point door-ajar bathroom pool}; do
    if ! $NICE "$EVAL" reference --scene "scenes/$scene/$scene.gltf" --algorithm bdpt \
        --spp "$(ref_spp "$scene")" --width "$W" --height "$H" --layers 1024 --quiet \
        --out "$OUT/$scene-ref.exr" >"$OUT/$scene-ref.txt"; then
        failed="$failed $scene:reference"
        continue
    fi
    head -3 "$OUT/$scene-ref.txt"
    if [ "${REUSE:-0}" = 1 ] && [ -f "$OUT/$scene-mpp$MPP.json" ]; then
        echo "== $scene mpp$MPP: reusing $OUT/$scene-mpp$MPP.json" >&2
    else
        quality "mpp$MPP" "$scene" --algorithms "$ALGORITHMS" --mpp "$MPP" --seeds "$SEEDS" ||
            continue
    fi
    [ "${EQUAL_TIME:-1}" = 1 ] || continue
    if [ -z "${PT_SPP:-}" ] && ! { [ "${REUSE:-0}" = 1 ] && [ -f "$OUT/$scene-pt-calibration.json" ]; }; then
        quality pt-calibration "$scene" --algorithms pt --spp "$CAL_SPP" --seeds 1 >/dev/null || continue
    fi
    for at in ${EQUAL_TIME_AT:-mlt}; do
        # ALGORITHM or ALGORITHM*FACTOR: pt gets FACTOR times that algorithm's 32-mpp time.
        algorithm=${at%%\**}
        factor=1
        [ "$algorithm" = "$at" ] || factor=${at#*\*}
        name=equal-time
        [ "$algorithm" = mlt ] || name=equal-time-$algorithm
        [ "$factor" = 1 ] || name=$name-x$factor
        spp=${PT_SPP:-}
        if [ -z "$spp" ]; then
            mine=$(json_field "$OUT/$scene-mpp$MPP.json" "$algorithm" seconds_mean)
            pt=$(json_field "$OUT/$scene-pt-calibration.json" pt seconds_mean)
            spp=$(python3 -c "import sys; print(max(1, round($CAL_SPP * $factor * $mine / $pt)))")
            echo "$scene: pt at $spp spp (pt $CAL_SPP spp took $pt s, $algorithm $MPP mpp $mine s, x $factor)" >&2
        fi
        quality "$name" "$scene" --algorithms "pt,$ALGORITHMS" --spp "$spp" \
            --seeds "$SEEDS" --equal-time || continue
    done
done
[ -z "$failed" ] || { echo "$(basename "$0"): failed:$failed" >&2; exit 1; }
