#!/bin/bash
# Pastes the blocks of README.md's "A 5-minute tour" into a shell, in order, as a new user does
# after `make demo`, and fails when any command fails. The only edits: free ports instead of
# 50051 and 8080 and a private store instead of /tmp/partita-store, so that the test can run beside
# others. Python blocks run with /usr/bin/python3 and the PYTHONPATH their comment names.
#   readme_tour_test.sh REPO BUILD_DIR
set -euo pipefail
repo=$(cd "$1" && pwd)
build=$(cd "$2" && pwd)
work=$(mktemp -d "${TMPDIR:-/tmp}/partita-tour.XXXXXX")
trap 'rm -rf "$work"' EXIT
ln -s "$build" "$work/build"
ln -s "$repo/scenes" "$work/scenes"
ln -s "$repo/client" "$work/client"
free_port() {
    /usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}
port=$(free_port)
http_port=$(free_port)

/usr/bin/python3 - "$repo/README.md" "$work/tour.sh" "$port" "$work/store" "$http_port" <<'PY'
import re, sys
readme, out, port, store, http_port = sys.argv[1:]
text = open(readme).read()
section = text.split("## A 5-minute tour", 1)[1].split("\n## ", 1)[0]
# The option summary after the tour is a list, not commands.
section = section.split("Every render option", 1)[0]
lines = ["set -euo pipefail", "trap 'kill $(jobs -p) 2>/dev/null || true' EXIT", "set -x"]
for lang, body in re.findall(r"```(sh|python)\n(.*?)```", section, re.S):
    body = body.replace("127.0.0.1:50051", "127.0.0.1:" + port).replace("/tmp/partita-store", store)
    body = body.replace("127.0.0.1:8080", "127.0.0.1:" + http_port)
    if lang == "sh":
        lines.append(body)
    else:
        lines += ["export PYTHONPATH=build/python:client/python",
                  "/usr/bin/python3 - <<'PYTHON'", body + "PYTHON"]
blocks = len(re.findall(r"```(sh|python)\n", section))
if blocks < 4:
    sys.exit("README.md's tour has %d code blocks, expected at least 4" % blocks)
open(out, "w").write("\n".join(lines) + "\n")
PY

cd "$work"
bash tour.sh
for f in glass.exr cornell.exr sweep/sweep.csv; do
    [ -s "$f" ] || { echo "readme tour: $f was not written" >&2; exit 1; }
done
echo "readme tour: every block ran"
