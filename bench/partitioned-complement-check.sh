#!/bin/sh
# A check, independent of partita-eval's code, of the complement's reference that `quality`
# measures partitioned's "complement" layer against (combined minus the reference's layers of the
# K types), with oiiotool only:
#  1. the reference's layers (every type, "other" included) sum to its combined image;
#  2. the sum of the layers of every type but the K types (what the complement holds) equals the
#     combined image minus the K types' layers;
#  3. a partitioned render of the same seed and settings (partita-local) has a complement layer
#     whose RMS error against (2) is the `rmse` of the complement in quality's JSON for that seed.
#   bench/partitioned-complement-check.sh REF.exr QUALITY.json [SEED]   (SEED default: the first)
# The scene, size, budget and pre-pass size are read from the JSON; needs build-bench's
# partita-local (cmake --build build-bench --target partita-local).
set -eu
cd "$(dirname "$0")/.."
REF=$1
JSON=$2
SEED=${3:-}
LOCAL=${PARTITA_LOCAL:-build-bench/tools/local/partita-local}
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
eval "$(python3 - "$JSON" "$SEED" <<'EOF'
import json, sys
j = json.load(open(sys.argv[1]))
r = next(r for r in j["results"] if r["algorithm"] == "partitioned")
seed = next(s for s in r["per_seed"] if not sys.argv[2] or s["seed"] == int(sys.argv[2]))
types = [e["layer"] for e in seed["partitions"] if e["layer"] != "complement"]
rmse = next(e["rmse"] for e in seed["partitions"] if e["layer"] == "complement")
boot = int(seed["statistics"]["prepass_samples"])
print(f"SCENE={j['scene']} W={j['width']} H={j['height']} MPP={r['mpp']:.0f} S={seed['seed']} "
      f"BOOT={boot} TYPES='{' '.join(types)}' RMSE={rmse!r}")
EOF
)"
echo "reference $REF; seed $S; K types: $TYPES; quality's complement RMSE $RMSE"
layers=$(oiiotool --info -v "$REF" | sed -n 's/^ *channel list: //p' | tr ',' '\n' |
    sed -n 's/^ *\(.*\)\.R$/\1/p')
echo "$(echo "$layers" | wc -l) layers in the reference"
# sum CHANNEL NAMES... : a one-channel image, the sum of NAME.CHANNEL over the names.
sum() {
    c=$1
    shift
    list=$(for n in "$@"; do printf '%s.%s,' "$n" "$c"; done)
    oiiotool "$REF" --ch "${list%,}" --chsum -d float -o "$TMP/sum.$c.exr"
}
rgb() {  # rgb OUT NAMES...: the three sums as one RGB image
    out=$1
    shift
    for c in R G B; do sum $c "$@" && mv "$TMP/sum.$c.exr" "$TMP/$out.$c.exr"; done
    oiiotool "$TMP/$out.R.exr" "$TMP/$out.G.exr" --chappend "$TMP/$out.B.exr" --chappend \
        --chnames R,G,B -d float -o "$TMP/$out.exr"
}
# shellcheck disable=SC2086
rgb all $layers
rest=$(echo "$layers" | grep -vxF "$(echo $TYPES | tr ' ' '\n')")
# shellcheck disable=SC2086
rgb rest $rest
# shellcheck disable=SC2086
rgb types $TYPES
oiiotool "$REF" --ch R,G,B -d float -o "$TMP/combined.exr"
oiiotool "$TMP/combined.exr" "$TMP/types.exr" --sub -d float -o "$TMP/minus.exr"
echo "1. the sum of all $(echo "$layers" | wc -l) layers against the combined image:"
diff() { oiiotool "$1" "$2" --diff 2>&1 | grep -E 'RMS error|Max error' || true; }
diff "$TMP/all.exr" "$TMP/combined.exr"
echo "2. the sum of the $(echo "$rest" | wc -l) other layers against combined minus the K types:"
diff "$TMP/rest.exr" "$TMP/minus.exr"
echo "3. partita-local render, seed $S, $MPP mpp, its complement against (2):"
nice -n 10 "$LOCAL" render "$SCENE" --algorithm partitioned --mpp "$MPP" --seed "$S" \
    --width "$W" --height "$H" --bootstrap "$BOOT" --out "$TMP/render.exr" >/dev/null 2>&1
oiiotool "$TMP/render.exr" --ch complement.R,complement.G,complement.B --chnames R,G,B \
    -d float -o "$TMP/complement.exr"
diff "$TMP/complement.exr" "$TMP/rest.exr"
echo "quality's figure for that seed: RMSE $RMSE"
