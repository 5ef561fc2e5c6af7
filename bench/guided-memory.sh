#!/bin/sh
# What guided's partitions and guide buffers cost in memory and time at 1280x720 with K = 10
# (issue #13 item 4): per scene, a cheap pt reference (2 spp, one type layer, not cached: only
# the statistics and memory matter), then for each of mlt, partitioned and guided a process of
# its own running `quality --algorithms A,A --mpp MEM_MPP --seeds 1 --bootstrap BOOTSTRAP --k K`
# (a tiny mutation budget: the pre-pass, the guides and the burn-in run in full). Each algorithm
# renders seed 1 twice in its process: the first render's peak increase is a cold process's, the
# second's a warm one's (it may reuse pages the first freed). guided's JSON has the guides'
# statistics: guide_bytes (G-buffer + support masks, kept through the render), gbuffer_seconds,
# denoise_seconds, guide_seconds (G-buffer, pre-pass images, denoise, thresholds). With
# TIMELINE=1 (default) guided and partitioned also render once through partita-local under
# bench/rss-timeline.py: resident memory sampled every 2 ms (OUT/<scene>-<size>-<A>-rss.csv) and
# the progress bar's redraws on a pseudo-terminal with their times (-events.txt: where the
# phases prepass, guides and render begin), the render's statistics from its EXR (-stats.txt),
# which shows the denoiser's transient apart from the chains' memory. partita-local resolves a
# preview every second (RenderSettings::previewIntervalSeconds, as a daemon job with previews
# does): its peaks are those resolves, not the harness's (no previews). The renders keep LAYERS
# type layers (default 32, the film's default). A scene that fails does not stop the others.
#   bench/guided-memory.sh   (SIZE=1280x720, MEM_MPP=1, K=10, BOOTSTRAP=100000, LAYERS=32,
#                             SCENES="cornell-glass ...", TIMELINE=1)
set -eu
cd "$(dirname "$0")/.."
EVAL=${PARTITA_EVAL:-build-bench/bench/partita-eval}
LOCAL=${PARTITA_LOCAL:-build-bench/tools/local/partita-local}
SIZE=${SIZE:-1280x720}
W=${SIZE%x*}
H=${SIZE#*x}
MEM_MPP=${MEM_MPP:-1}
K=${K:-10}
BOOTSTRAP=${BOOTSTRAP:-100000}
LAYERS=${LAYERS:-32}
NICE=${NICE-nice -n 10}
OUT=${OUT:-build-bench/guided-memory}
mkdir -p "$OUT"
failed=
for scene in ${SCENES:-cornell cornell-glass cornell-point door-ajar bathroom pool}; do
    gltf=scenes/$scene/$scene.gltf
    ref=$OUT/$scene-$SIZE-ref.exr
    echo "== $scene $SIZE ($(date +%H:%M:%S))" >&2
    if ! $NICE "$EVAL" reference --scene "$gltf" --algorithm pt --spp 2 --width "$W" --height "$H" \
        --layers 1 --no-cache --quiet --out "$ref" >/dev/null; then
        failed="$failed $scene:reference"
        continue
    fi
    for a in mlt partitioned guided; do
        $NICE "$EVAL" quality --scene "$gltf" --reference "$ref" --algorithms "$a,$a" \
            --mpp "$MEM_MPP" --k "$K" --bootstrap "$BOOTSTRAP" --seeds 1 --quiet \
            --layers "$LAYERS" --table-layers 0 --json "$OUT/$scene-$SIZE-$a.json" \
            >"$OUT/$scene-$SIZE-$a.txt" || failed="$failed $scene:$a"
    done
    if [ "${TIMELINE:-1}" = 1 ]; then
        for a in partitioned guided; do
            base=$OUT/$scene-$SIZE-$a
            $NICE python3 bench/rss-timeline.py --out "$base-rss.csv" --events "$base-events.txt" -- \
                "$LOCAL" render "$gltf" --algorithm "$a" --mpp "$MEM_MPP" --k "$K" \
                --bootstrap "$BOOTSTRAP" --width "$W" --height "$H" --layers "$LAYERS" \
                --out "$base-local.exr" 2>"$base-rss.txt" || failed="$failed $scene:$a-timeline"
            iinfo -v "$base-local.exr" 2>/dev/null | grep 'partita:stat:' >"$base-stats.txt" || true
            rm -f "$base-local.exr" "$base-local.png"
        done
    fi
    rm -f "$ref"
done
[ -z "$failed" ] || { echo "guided-memory: failed:$failed" >&2; exit 1; }
