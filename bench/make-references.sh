#!/bin/sh
# The reference of every shipped scene (scenes/*/*.gltf), found in the cache or rendered:
#   bench/make-references.sh [more `partita-eval reference` options, e.g. --force --algorithm pt]
# Budget and size come from the environment: SPP (default 1024), WIDTH and HEIGHT (320x240, the
# harness's default), so that `quality` runs at that size find them. PARTITA_EVAL names the
# harness (default build-bench/bench/partita-eval), PARTITA_REFERENCE_CACHE the cache folder.
# A scene that fails (an algorithm not built yet) stops the script with partita-eval's message.
set -eu
cd "$(dirname "$0")/.."
EVAL=${PARTITA_EVAL:-build-bench/bench/partita-eval}
for scene in scenes/*/*.gltf; do
    "$EVAL" reference --scene "$scene" --spp "${SPP:-1024}" --width "${WIDTH:-320}" \
        --height "${HEIGHT:-240}" "$@"
done
