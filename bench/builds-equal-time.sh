#!/usr/bin/env bash
# Two builds of partita-local side by side at equal time: does a change to an estimator's cost
# lower its error per second? Per scene, seed and algorithm, the baseline build (BASE) and the
# build under test (NEW) render in turn with a time budget, and each image's RMSE (RGB, the
# combined image) against the scene's reference is printed, with the pair's ratio NEW / BASE.
#   BASE=/path/old/partita-local NEW=build-bench/tools/local/partita-local \
#   bench/builds-equal-time.sh   (SECONDS_EACH=10, SEEDS="1 2", SIZE=256x192,
#                                 SCENES="cornell-glass bathroom pool", ALGORITHMS="mlt partitioned",
#                                 REFS=/tmp/ref: REFS/S-256.exr, e.g. partita-eval reference
#                                 --algorithm pt --spp 1024 --width 256 --height 192)
# One line per pair on stdout: scene algorithm seed rmse_base rmse_new new/base mutations_base
# mutations_new.
set -eu
cd "$(dirname "$0")/.."
: "${BASE:?the baseline partita-local}"
NEW=${NEW:-build-bench/tools/local/partita-local}
SIZE=${SIZE:-256x192}
REFS=${REFS:-/tmp/ref}
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT

rmse() {  # the RGB RMS error of $1 against $2, from oiiotool's --diff report
    oiiotool "$1" --ch R,G,B "$2" --ch R,G,B --diff 2>/dev/null |
        awk '/RMS error/ { print $4; exit }'
}
stat() {  # statistic $2 of EXR $1
    oiiotool --info -v "$1" | awk -v k="partita:stat:$2:" '$1 == k { gsub(/"/, "", $2); print $2 }'
}

for scene in ${SCENES:-cornell-glass bathroom pool}; do
    ref=$REFS/$scene-256.exr
    for algorithm in ${ALGORITHMS:-mlt partitioned}; do
        for seed in ${SEEDS:-1 2}; do
            line="$scene $algorithm $seed"
            for build in "$BASE" "$NEW"; do
                "$build" render "scenes/$scene/$scene.gltf" --algorithm "$algorithm" \
                    --seconds "${SECONDS_EACH:-10}" --seed "$seed" --width "${SIZE%x*}" \
                    --height "${SIZE#*x}" --quiet --preview-interval 0 --out "$OUT/r.exr" \
                    >/dev/null
                line="$line $(rmse "$OUT/r.exr" "$ref") $(stat "$OUT/r.exr" mutations)"
            done
            echo "$line" | awk '{ printf "%s %s %s %s %s %.3f %s %s\n", $1, $2, $3, $4, $6, $6 / $4, $5, $7 }'
        done
    done
done
