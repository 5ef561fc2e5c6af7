#!/bin/bash
# The independence mutation's rate at equal time (issue #22 item 2; docs/mlt-study.md,
# "Suspicious" 2): mlt at 128x96 under a time budget (SECONDS_BUDGET, default 5), the direct light
# at a fixed 16 spp so that only the chains differ between rates, SEEDS seeds from SEED, one rate
# after another per scene, against the references REF/ref-<scene>-128.exr
# (partita-eval reference --scene S --spp 512 --width 128 --height 96 --out ...).
# Prints per scene and rate: RMSE mean, its std over seeds, mutations per pixel, the independence
# mutation's acceptance, stuck and type-bound chains per seed.
cd "$(dirname "$0")/.."
E=${EVAL:-build/bench/partita-eval}
REF=${REF:-references-128}
OUT=${OUT:-large-step-rate}
mkdir -p "$OUT"
for scene in ${SCENES:-cornell-glass bathroom pool}; do
  for rate in ${RATES:-0 0.05 0.1 0.2}; do
    json=$OUT/$scene-s${SEED:-1}-r$rate.json
    $E quality --scene scenes/$scene/$scene.gltf --reference "$REF/ref-$scene-128.exr" \
      --algorithms mlt --seconds "${SECONDS_BUDGET:-5}" --direct-spp 16 --seeds "${SEEDS:-4}" \
      --seed "${SEED:-1}" --large-step-rate "$rate" --json "$json" > "${json%.json}.log" 2>&1
    python3 -c "
import json; r = json.load(open('$json'))['results'][0]
print('$scene', $rate, r['rmse_mean'], r['rmse_std'], r['units_per_pixel_mean'],
      r['acceptance_per_mutation'].get('independence'), r['stuck_chains'], r['type_bound_chains'])"
  done
done
