#!/bin/bash
# Loads and renders every .gltf/.glb under a folder with partita-local, and checks the rule for
# files the project has never seen: each one renders, or fails with exit code 1 and exactly one
# line on stderr; none crashes, hangs or fails silently.
#
#   scripts/check-gltf-corpus.sh DIR [PARTITA_LOCAL]
#
# PARTITA_LOCAL defaults to build/tools/local/partita-local. Each file is rendered at 32x24 with
# 1 spp on one thread, with 60 s to finish. Prints one line per file that breaks the rule, then
# counts and the most common error messages; exits 1 if any file broke the rule.
set -u
dir=${1:?usage: $0 DIR [PARTITA_LOCAL]}
bin=${2:-build/tools/local/partita-local}
[ -x "$bin" ] || { echo "$0: $bin is not an executable (build first)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
rendered=0 refused=0 broken=0
: > "$work/errors"
while IFS= read -r -d '' file; do
    timeout 60 "$bin" render "$file" --width 32 --height 24 --spp 1 --threads 1 \
        --out "$work/out.exr" </dev/null >/dev/null 2>"$work/stderr"
    rc=$?
    lines=$(grep -c . "$work/stderr")
    if [ $rc -eq 0 ]; then
        rendered=$((rendered + 1))
    elif [ $rc -eq 1 ] && [ "$lines" -eq 1 ]; then
        refused=$((refused + 1))
        sed -e "s|$dir[^ ]*|FILE|g" "$work/stderr" >> "$work/errors"
    else
        broken=$((broken + 1))
        case $rc in
            124) why="no result within 60 s" ;;
            1) why="$lines lines on stderr" ;;
            *) why="exit code $rc" ;;
        esac
        echo "BROKEN $file: $why: $(head -c 300 "$work/stderr" | tr '\n' '|')"
    fi
done < <(find "$dir" \( -name '*.gltf' -o -name '*.glb' \) -print0 | sort -z)
echo "rendered $rendered, refused with one line $refused, broken $broken"
echo "most common refusals:"
cut -c1-110 "$work/errors" | sort | uniq -c | sort -rn | head -15
[ $broken -eq 0 ]
