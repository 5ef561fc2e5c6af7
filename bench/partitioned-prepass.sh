#!/bin/sh
# partitioned's pre-pass time and memory on every shipped scene (issue #12), at each size of
# SIZES (default 128x96 640x360 1280x720: the pre-pass has a fixed sample count, so its time
# should not depend on the size). Per scene and size: a cheap pt reference (2 spp, one type
# layer, not cached: `quality` needs one of the render's size, and only the peak memory and the
# statistics are of interest here), then `quality --algorithms partitioned,partitioned --mpp
# PREPASS_MPP --seeds SEEDS` with the default pre-pass (BOOTSTRAP samples, default 100000) and a
# tiny mutation budget, so that the chains (burn-in included) cost little. partitioned runs twice
# with the same seeds in one process: the first one's peak increase includes what a cold process
# allocates once, the second's is a warm process's (which may reuse pages the first freed: the
# truth lies between). Its JSON (OUT/<scene>-<size>.json) has the
# pre-pass seconds, samples, types and half-B records (statistics prepass_*), the peak RSS and
# its increase over the resident scene and reference, and the daemon's memory estimate of such a
# job (server/job_memory.h). With MLT=1 (the default) mlt renders the same in a process of its own
# (OUT/<scene>-<size>-mlt.json), for what partitioned adds over it. The renders keep LAYERS type
# layers (default 32, the film's default); a partition's film resolves that many too. A scene
# that fails does not stop the others.
#   bench/partitioned-prepass.sh   (SIZES="128x96 640x360 1280x720", PREPASS_MPP=1, SEEDS=1,
#                                   LAYERS=32, MLT=1)
set -eu
cd "$(dirname "$0")/.."
EVAL=${PARTITA_EVAL:-build-bench/bench/partita-eval}
BOOTSTRAP=${BOOTSTRAP:-100000}
NICE=${NICE-nice -n 10}
OUT=${OUT:-build-bench/partitioned-prepass}
mkdir -p "$OUT"
failed=
for scene in ${SCENES:-cornell cornell-glass cornell-point door-ajar bathroom pool}; do
    for size in ${SIZES:-128x96 640x360 1280x720}; do
        gltf=scenes/$scene/$scene.gltf
        ref=$OUT/$scene-$size-ref.exr
        echo "== $scene $size" >&2
        if $NICE "$EVAL" reference --scene "$gltf" --algorithm pt --spp 2 --width "${size%x*}" \
            --height "${size#*x}" --layers 1 --no-cache --quiet --out "$ref" >/dev/null &&
            $NICE "$EVAL" quality --scene "$gltf" --reference "$ref" --algorithms partitioned,partitioned \
                --mpp "${PREPASS_MPP:-1}" --bootstrap "$BOOTSTRAP" --seeds "${SEEDS:-1}" --quiet \
                --layers "${LAYERS:-32}" --table-layers 0 --json "$OUT/$scene-$size.json" \
                >"$OUT/$scene-$size.txt" &&
            { [ "${MLT:-1}" != 1 ] || $NICE "$EVAL" quality --scene "$gltf" --reference "$ref" \
                --algorithms mlt --mpp "${PREPASS_MPP:-1}" --bootstrap "$BOOTSTRAP" --seeds "${SEEDS:-1}" \
                --quiet --layers "${LAYERS:-32}" --table-layers 0 --json "$OUT/$scene-$size-mlt.json" \
                >"$OUT/$scene-$size-mlt.txt"; }; then
            cat "$OUT/$scene-$size.txt"
        else
            failed="$failed $scene:$size"
        fi
        rm -f "$ref"
    done
done
[ -z "$failed" ] || { echo "partitioned-prepass: failed:$failed" >&2; exit 1; }
