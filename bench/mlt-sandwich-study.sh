#!/bin/bash
# "Suspicious" 2 redone (issue #22 item 2; docs/mlt-study.md): mlt without (large_step_rate 0)
# and with the independence mutation (RATE, default the default 0.1), per seed and budget, on
# bathroom and pool at 128x96 with every type as a layer. Then bench/mlt-sandwich-table.py OUT REF.
cd "$(dirname "$0")/.."
PL=${LOCAL:-build/tools/local/partita-local}
OUT=${OUT:-sandwich}
mkdir -p "$OUT"
for scene in bathroom pool; do
  for seed in ${SEEDS_LIST:-1 4}; do
    for mpp in 256 1024; do
      for rate in 0 ${RATE:-0.1}; do
        $PL render scenes/$scene/$scene.gltf --algorithm mlt --width 128 --height 96 --mpp $mpp \
          --seed $seed --layers 1024 --large-step-rate $rate \
          --out "$OUT/$scene-s$seed-m$mpp-r$rate.exr" > /dev/null 2>&1
        echo "$scene seed $seed $mpp mpp rate $rate done"
      done
    done
  done
done
