#!/bin/sh
# pt, bdpt and mlt on every shipped scene at equal time (issue #11, item 7): a BDPT reference per
# scene (the cache of bdpt-study.sh and make-references.sh), then `quality` with bdpt and mlt
# given pt's mean wall time at PT_SPP, 4 seeds. The three algorithms of a scene run side by side
# in one process, so load from elsewhere on the machine hits them alike.
#   bench/mlt-study.sh        (SIZE=128x96, REF_SPP=1024, PT_SPP=64; JSON in OUT/<scene>-pt<PT_SPP>.json)
set -eu
cd "$(dirname "$0")/.."
EVAL=${PARTITA_EVAL:-build-bench/bench/partita-eval}
SIZE=${SIZE:-128x96}
W=${SIZE%x*}
H=${SIZE#*x}
PT_SPP=${PT_SPP:-64}
OUT=${OUT:-build-bench/mlt-study}
mkdir -p "$OUT"
failed=
for scene in ${SCENES:-cornell cornell-glass cornell-point door-ajar bathroom pool}; do
    gltf=scenes/$scene/$scene.gltf
    "$EVAL" reference --scene "$gltf" --algorithm bdpt --spp "${REF_SPP:-1024}" --width "$W" \
        --height "$H" --layers 1024 --quiet --out "$OUT/$scene-ref.exr"
    "$EVAL" quality --scene "$gltf" --reference "$OUT/$scene-ref.exr" --algorithms pt,bdpt,mlt \
        --spp "$PT_SPP" --seeds 4 --equal-time --quiet --json "$OUT/$scene-pt$PT_SPP.json" ||
        failed="$failed $scene"
done
# A scene whose quality run failed (e.g. mlt cancelled for running past its time budget) does
# not stop the others.
[ -z "$failed" ] || { echo "mlt-study: quality failed for:$failed" >&2; exit 1; }
