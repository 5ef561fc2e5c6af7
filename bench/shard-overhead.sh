#!/bin/sh
# What sharding costs (issue #14 item 6), with partita-local as a cluster runs it: per algorithm
# the one-process render, `plan` (its start-up: nothing for pt, the bootstrap for mlt), the
# shards run as N concurrent processes of THREADS/N threads each (a single-node stand-in for N
# machines; SHARD_THREADS overrides the threads of each), and `merge`; wall seconds of each step, plan and shard file sizes, and whether the
# merged EXR equals the one-process EXR bit for bit (idiff -fail 0). The speed-up is
# one-process seconds over plan + slowest concurrent shard + merge.
#   bench/shard-overhead.sh   (SCENE=cornell-glass SIZE=1280x720 SPP=16 MPP=4 SHARDS="1 2"
#                              THREADS=$(nproc) SHARD_THREADS= ALGORITHMS="pt mlt")
# With THREADS=1 SHARD_THREADS=1 the speed-up is that of N one-core machines over one, up to
# the cores this machine has.
set -eu
cd "$(dirname "$0")/.."
LOCAL=${PARTITA_LOCAL:-build/tools/local/partita-local}
SCENE=${SCENE:-cornell-glass}
SIZE=${SIZE:-1280x720}
W=${SIZE%x*}
H=${SIZE#*x}
THREADS=${THREADS:-$(nproc)}
OUT=${OUT:-build/shard-overhead}
mkdir -p "$OUT"
gltf=scenes/$SCENE/$SCENE.gltf
now() { date +%s.%N; }
seconds() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.3f", b - a }'; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.3f", a / b }'; }
printf '%-5s %6s %9s %9s %9s %9s %9s %10s %10s %8s %s\n' algorithm shards one_s plan_s \
    shards_s merge_s speedup plan_bytes shard_bytes overhead identical
for alg in ${ALGORITHMS:-pt mlt}; do
    case $alg in
    pt | bdpt) budget="--spp ${SPP:-16}" ;;
    *) budget="--mpp ${MPP:-4}" ;;
    esac
    job="$gltf --algorithm $alg $budget --width $W --height $H --seed 3"
    t0=$(now)
    # No previews: the shards make none either (a preview a second costs a 33-layer resolve).
    "$LOCAL" render $job --threads "$THREADS" --quiet --preview-interval 0 --out "$OUT/$alg-one.exr"
    one=$(seconds "$t0" "$(now)")
    for n in ${SHARDS:-1 2}; do
        per=${SHARD_THREADS:-$((THREADS / n))}
        [ "$per" -ge 1 ] || per=1
        rm -f "$OUT/$alg-$n-"*.shard
        t0=$(now)
        "$LOCAL" plan $job --threads "$THREADS" --shards "$n" --quiet --out "$OUT/$alg-$n.plan"
        t1=$(now)
        i=0
        while [ "$i" -lt "$n" ]; do
            "$LOCAL" render --plan "$OUT/$alg-$n.plan" --shard "$i" --threads "$per" --quiet \
                --out "$OUT/$alg-$n-$i.shard" &
            i=$((i + 1))
        done
        wait
        t2=$(now)
        "$LOCAL" merge --plan "$OUT/$alg-$n.plan" "$OUT/$alg-$n-"*.shard --quiet \
            --out "$OUT/$alg-$n-merged.exr"
        t3=$(now)
        plan=$(seconds "$t0" "$t1")
        work=$(seconds "$t1" "$t2")
        merge=$(seconds "$t2" "$t3")
        total=$(seconds "$t0" "$t3")
        speedup=$(ratio "$one" "$total")
        overhead=$(ratio "$(awk -v a="$plan" -v b="$merge" 'BEGIN { print a + b }')" "$total")
        planBytes=$(stat -c %s "$OUT/$alg-$n.plan")
        shardBytes=$(stat -c %s "$OUT/$alg-$n-0.shard")
        if idiff -a -fail 0 -warn 0 "$OUT/$alg-one.exr" "$OUT/$alg-$n-merged.exr" >/dev/null 2>&1; then
            same=yes
        else
            same=NO
        fi
        printf '%-5s %6s %9.2f %9.2f %9.2f %9.2f %9s %10s %10s %8s %s\n' "$alg" "$n" "$one" \
            "$plan" "$work" "$merge" "$speedup" "$planBytes" "$shardBytes" "$overhead" "$same"
    done
done
