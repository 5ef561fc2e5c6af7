#!/usr/bin/env bash
# The sanitizer runs of CI (.ci/run, after `make test`): `make test-asan` (ASan + UBSan on the
# unit, server and service tests) and `make test-tsan` (TSan on the threaded tests), each within
# what is left of CI's time.
# Usage: scripts/ci-sanitizers.sh DEADLINE   (DEADLINE: seconds since the epoch)
#
# Each needs a clang build of its own. With ccache warm (the machine built them before) that is
# minutes; from a cold cache it is 45-50 min on 2 cores, and both would not fit CI's 90 minutes
# after `make test`. So: a run that fails, or any sanitizer report, fails CI; a run that the
# deadline stops, or that has no time to start (less than MIN_SECONDS left), is reported as not
# finished ("NOT FINISHED") and does not fail CI: a slow machine must not block every landing.
set -uo pipefail
cd "$(dirname "$0")/.."
deadline=${1:?usage: scripts/ci-sanitizers.sh DEADLINE}
MIN_SECONDS=${MIN_SECONDS:-600}
status=0
for target in test-asan test-tsan; do
  left=$((deadline - $(date +%s)))
  if ((left < MIN_SECONDS)); then
    echo "ci-sanitizers: make $target NOT FINISHED: not started, ${left} s left of CI's time"
    continue
  fi
  echo "ci-sanitizers: make $target (at most ${left} s)"
  start=$(date +%s)
  # Its own process group, so that the deadline stops ctest and the daemons the tests started.
  setsid make "$target" &
  pid=$!
  while kill -0 "$pid" 2>/dev/null && (($(date +%s) < deadline)); do sleep 5; done
  if kill -0 "$pid" 2>/dev/null; then
    kill -TERM -- "-$pid" 2>/dev/null
    sleep 10
    kill -KILL -- "-$pid" 2>/dev/null
    wait "$pid" 2>/dev/null
    echo "ci-sanitizers: make $target NOT FINISHED: stopped at CI's deadline after $(($(date +%s) - start)) s"
    continue
  fi
  wait "$pid"
  rc=$?
  echo "ci-sanitizers: make $target exited $rc after $(($(date +%s) - start)) s"
  ((rc == 0)) || status=1
done
exit $status
