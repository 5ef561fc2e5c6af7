#!/usr/bin/env bash
# Compare Partita's path tracer with Blender Cycles on a diffuse scene (see README.md here).
#
#   scripts/cycles/run.sh                      # cornell, 128x128, 4 + 4 seeds, a few minutes each
#   SCENE=scenes/x/x.gltf PARTITA_SPP=512 CYCLES_SPP=16 scripts/cycles/run.sh
#
# Settings (environment): SCENE, WIDTH, HEIGHT, MAX_DEPTH (Partita's convention: scattering
# vertices), PARTITA_SPP (per pixel), CYCLES_SPP (per Cycles cell; k x k cells per pixel,
# SUPERSAMPLE k, default 4, so a pixel gets k^2 x CYCLES_SPP camera samples), SEEDS, BLOCK,
# ALPHA (family-wise), OUT (work directory), CHECKS=0 to skip the quick unit checks.
# Everything runs single-threaded under nice -n 19. Exit status 0 when every check passes.
set -euo pipefail
cd "$(dirname "$0")/../.."

SCENE=${SCENE:-scenes/cornell/cornell.gltf}
WIDTH=${WIDTH:-128}
HEIGHT=${HEIGHT:-128}
MAX_DEPTH=${MAX_DEPTH:-16}
PARTITA_SPP=${PARTITA_SPP:-2048}
CYCLES_SPP=${CYCLES_SPP:-64}
SUPERSAMPLE=${SUPERSAMPLE:-4}
SEEDS=${SEEDS:-"1 2 3 4"}
BLOCK=${BLOCK:-8}
ALPHA=${ALPHA:-0.01}
OUT=${OUT:-/tmp/cycles-run}
CHECKS=${CHECKS:-1}

PARTITA=build/tools/local/partita-local
PY=/usr/bin/python3
HERE=scripts/cycles

[ -x "$PARTITA" ] || { echo "run.sh: $PARTITA is missing: build the project first" >&2; exit 2; }
if ! command -v blender >/dev/null; then
    if [ "$(id -u)" = 0 ]; then
        apt-get install -y --no-install-recommends blender
    else
        echo "run.sh: blender is missing: apt-get install --no-install-recommends blender" >&2
        exit 2
    fi
fi
$PY -c "import numpy, scipy, OpenImageIO" 2>/dev/null || {
    echo "run.sh: needs python3-numpy python3-scipy python3-openimageio" >&2; exit 2; }

mkdir -p "$OUT"
status=0

partita() {  # scene out seed spp w h depth
    nice -n 19 "$PARTITA" render "$1" --out "$2" --seed "$3" --spp "$4" --width "$5" \
        --height "$6" --max-depth "$7" --threads 1 --quiet
}
cycles() {  # scene out seed spp w h depth
    local log="${2%.exr}.log"
    if ! nice -n 19 blender -b -noaudio --factory-startup -t 1 -P "$HERE/render_cycles.py" -- \
        --scene "$1" --out "$2" --seed "$3" --spp "$4" --width "$5" --height "$6" \
        --max-depth "$7" --supersample "$SUPERSAMPLE" --threads 1 >"$log" 2>&1; then
        cat "$log" >&2
        echo "run.sh: Cycles render failed (log: $log)" >&2
        exit 2
    fi
}

if [ "$CHECKS" = 1 ]; then
    # 1. Emission units and sidedness: emissive quad (1,1,1) x 1 straight ahead -> 1.0 everywhere.
    echo "== unit checks: emissive quad (units, one-/two-sided emission)"
    U="$OUT/units"
    mkdir -p "$U"
    $PY "$HERE/make_test_scenes.py" "$U"
    for q in front:1 back:0 double:1; do
        name=${q%%:*} want=${q##*:}
        partita "$U/quad-$name.gltf" "$U/p-$name.exr" 1 4 16 16 4
        cycles "$U/quad-$name.gltf" "$U/c-$name.exr" 1 4 16 16 4
        $PY - "$U/p-$name.exr" "$U/c-$name.exr" "$name" "$want" <<'EOF' || status=1
import sys, numpy as np, OpenImageIO as oiio
vals = []
for p in sys.argv[1:3]:
    b = oiio.ImageBuf(p)
    names = list(b.spec().channelnames)
    a = b.get_pixels(oiio.FLOAT)
    vals.append(np.stack([a[:, :, names.index(c)] for c in "RGB"], -1))
want = float(sys.argv[4])
ok = all(np.allclose(v, want, rtol=1e-5, atol=1e-6) for v in vals)
print("quad-%-6s want %.1f: Partita min %.6f max %.6f, Cycles min %.6f max %.6f -> %s"
      % (sys.argv[3], want, vals[0].min(), vals[0].max(), vals[1].min(), vals[1].max(),
         "ok" if ok else "MISMATCH"))
sys.exit(0 if ok else 1)
EOF
    done

    # 2. Depth convention: Partita --max-depth N = Cycles max_bounces N - 1, at N = 1 and 2.
    for d in 1 2; do
        echo "== depth check: $SCENE, 64x64, --max-depth $d (Cycles max_bounces $((d - 1)))"
        Dd="$OUT/depth$d"
        mkdir -p "$Dd"
        dscene=$($PY "$HERE/diffuse_variant.py" "$SCENE" "$Dd/scene")
        for s in 1 2 3 4; do
            partita "$dscene" "$Dd/p$s.exr" "$s" 256 64 64 "$d"
            cycles "$dscene" "$Dd/c$s.exr" "$s" 16 64 64 "$d"
        done
        # Depth 1 is reported but not counted: Cycles is 1.5-3.5% low where the ceiling light
        # arrives at grazing angles, where Partita matches a numerical integral of the direct
        # light (README.md, "Direct light at grazing angles").
        if ! $PY "$HERE/compare.py" --partita "$Dd"/p?.exr --cycles "$Dd"/c?.exr --block 8 \
            --alpha "$ALPHA" --json "$Dd/compare.json"; then
            if [ "$d" = 1 ]; then
                echo "   (depth 1: the known Cycles deviation at grazing light; not counted)"
            else
                status=1
            fi
        fi
    done
fi

# 3. The comparison.
echo "== main: $SCENE, ${WIDTH}x$HEIGHT, --max-depth $MAX_DEPTH, Partita $PARTITA_SPP spp," \
     "Cycles $CYCLES_SPP spp x ${SUPERSAMPLE}x$SUPERSAMPLE cells, seeds $SEEDS, ${BLOCK}x$BLOCK blocks"
M="$OUT/main"
mkdir -p "$M"
mscene=$($PY "$HERE/diffuse_variant.py" "$SCENE" "$M/scene")
p_files=() c_files=()
t0=$(date +%s)
for s in $SEEDS; do
    partita "$mscene" "$M/p$s.exr" "$s" "$PARTITA_SPP" "$WIDTH" "$HEIGHT" "$MAX_DEPTH"
    p_files+=("$M/p$s.exr")
done
t1=$(date +%s)
for s in $SEEDS; do
    cycles "$mscene" "$M/c$s.exr" "$s" "$CYCLES_SPP" "$WIDTH" "$HEIGHT" "$MAX_DEPTH"
    c_files+=("$M/c$s.exr")
done
t2=$(date +%s)
echo "render time (one thread, wall): Partita $((t1 - t0)) s, Cycles $((t2 - t1)) s"
$PY "$HERE/compare.py" --partita "${p_files[@]}" --cycles "${c_files[@]}" --block "$BLOCK" \
    --alpha "$ALPHA" --json "$M/compare.json" || status=1

echo "== $( [ $status = 0 ] && echo PASS || echo FAIL ) (outputs in $OUT)"
exit $status
