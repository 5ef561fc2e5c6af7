#!/usr/bin/env bash
# Equal-time study of issue #23 item 2 (docs/partition-classes.md): 256x192, 10 s a render, 2 seeds,
# references by pt (partita-eval reference --algorithm pt --spp 2048|1024|1024 --width 256
# --height 192 --out /tmp/ref/S-256.exr). Writes /tmp/q/S-{base,classes,auto-classes}.{txt,json}.
set -u
cd "$(dirname "$0")/.."
E=build-bench/bench/partita-eval
mkdir -p /tmp/q
for s in cornell-glass bathroom pool; do
  R=/tmp/ref/$s-256.exr
  $E quality --scene scenes/$s/$s.gltf --reference $R --algorithms pt,mlt,partitioned --seconds 10 --seeds 2 --estimators chains --partitions types --quiet --json /tmp/q/$s-base.json > /tmp/q/$s-base.txt 2>&1
  $E quality --scene scenes/$s/$s.gltf --reference $R --algorithms partitioned --seconds 10 --seeds 2 --estimators chains --partitions classes --quiet --json /tmp/q/$s-classes.json > /tmp/q/$s-classes.txt 2>&1
  $E quality --scene scenes/$s/$s.gltf --reference $R --algorithms partitioned --seconds 10 --seeds 2 --estimators auto --partitions classes --quiet --json /tmp/q/$s-auto-classes.json > /tmp/q/$s-auto-classes.txt 2>&1
  echo "$s done $(date)"
done
echo quality-done
