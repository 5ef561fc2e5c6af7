#!/bin/bash
# Where the guided move pays (issue #23 item 6; docs/partition-estimators.md): guided renders
# whose chains' pilot runs both moves, guided and lens, on every partition for half of a 40 s
# budget (~0.9 s per partition and move at 256x192), with estimators=chains (every partition
# has chains) and allocation=neyman (which runs the pilot). The statistics then hold, per
# partition, each move's v_g (the image error of its chains times their mutations: at the same
# target, proportional to the integrated autocorrelation time) and c_g. THROUGH=true is the
# paper's move (also for paths seen through specular surfaces), false today's default.
# Then bench/guided-move-table.py OUT.
cd "$(dirname "$0")/.."
PL=${LOCAL:-build/tools/local/partita-local}
OUT=${OUT:-guided-move}
mkdir -p "$OUT"
for scene in ${SCENES:-door-ajar cornell-glass pool}; do
  for seed in ${SEEDS_LIST:-1 2}; do
    $PL render scenes/$scene/$scene.gltf --algorithm guided --width 256 --height 192 \
      --seconds 40 --seed "$seed" --threads 2 --quiet --preview-interval 0 \
      --param pilot_share=0.5 --param estimators=chains --param allocation=neyman \
      --param through_specular="${THROUGH:-false}" \
      --out "$OUT/$scene-s$seed-through-${THROUGH:-false}.exr" > /dev/null 2>&1
    echo "$scene seed $seed done"
  done
done
