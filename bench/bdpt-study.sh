#!/bin/sh
# pt against bdpt on every shipped scene (issue #10, item 7): a BDPT reference per scene, then
# `quality` at equal samples per pixel and at equal time (bdpt gets pt's wall time), 4 seeds.
#   bench/bdpt-study.sh            (SIZE=128x96, REF_SPP=1024, SPP=16 by default; JSON in OUT)
set -eu
cd "$(dirname "$0")/.."
EVAL=${PARTITA_EVAL:-build-bench/bench/partita-eval}
SIZE=${SIZE:-128x96}
W=${SIZE%x*}
H=${SIZE#*x}
OUT=${OUT:-build-bench/bdpt-study}
mkdir -p "$OUT"
for scene in ${SCENES:-cornell cornell-glass cornell-point door-ajar bathroom pool}; do
    gltf=scenes/$scene/$scene.gltf
    "$EVAL" reference --scene "$gltf" --algorithm bdpt --spp "${REF_SPP:-1024}" --width "$W" \
        --height "$H" --layers 1024 --quiet --out "$OUT/$scene-ref.exr"
    "$EVAL" quality --scene "$gltf" --reference "$OUT/$scene-ref.exr" --algorithms pt,bdpt \
        --spp "${SPP:-16}" --seeds 4 --quiet --json "$OUT/$scene-equal-spp.json"
    "$EVAL" quality --scene "$gltf" --reference "$OUT/$scene-ref.exr" --algorithms pt,bdpt \
        --spp "${PT_SPP:-64}" --seeds 4 --equal-time --quiet --json "$OUT/$scene-equal-time.json"
done
