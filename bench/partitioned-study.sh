#!/bin/sh
# partitioned against mlt and pt on every shipped scene (issue #12): guided-study.sh with
# ALGORITHMS=mlt,partitioned, its outputs in build-bench/partitioned-study (OUT= to change):
# a BDPT reference per scene with every type layer, then `quality` at MPP mutations per pixel
# with the same start-up budget for both, and at equal time with pt (pt's spp calibrated to
# mlt's time). bench/partitioned-study-table.py turns the JSON into docs/partitioned-study.md's tables. Every
# variable of guided-study.sh applies (SIZE, REF_SPP, MPP, BOOTSTRAP, SEEDS, SCENES, ...).
#   bench/partitioned-study.sh   (SIZE=128x96, REF_SPP=1024, MPP=32, BOOTSTRAP=100000, SEEDS=4)
set -eu
cd "$(dirname "$0")/.."
ALGORITHMS=${ALGORITHMS:-mlt,partitioned} OUT=${OUT:-build-bench/partitioned-study} \
    exec bench/guided-study.sh
