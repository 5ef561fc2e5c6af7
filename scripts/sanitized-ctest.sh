#!/usr/bin/env bash
# ctest in a sanitizer build folder (make test-asan, make test-tsan): every sanitizer report,
# from the test executables and from the partitad and partita-local processes they start, is
# written to <build>/sanitizer-logs/ (log_path), and any report fails the run even where the
# test that started the process passed. Suppressions: tests/sanitizers/ (one comment each).
# Usage: scripts/sanitized-ctest.sh BUILD_DIR [ctest arguments...]
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "$1" && pwd)
shift
logs=$build/sanitizer-logs
rm -rf "$logs"
mkdir -p "$logs"
supp=$root/tests/sanitizers
export ASAN_OPTIONS="log_path=$logs/asan:detect_leaks=1:check_initialization_order=1:strict_init_order=1:detect_stack_use_after_return=1"
export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="log_path=$logs/ubsan:print_stacktrace=1:halt_on_error=1:suppressions=$supp/ubsan.supp"
export TSAN_OPTIONS="log_path=$logs/tsan:suppressions=$supp/tsan.supp:print_suppressions=0:second_deadlock_stack=1:history_size=4"

start=$(date +%s)
(cd "$build" && ctest --output-on-failure "$@")
status=$?
echo "sanitized ctest in $(basename "$build"): $(($(date +%s) - start)) s"
reports=("$logs"/*)
if [ -e "${reports[0]}" ]; then
  echo "sanitizer reports (${#reports[@]} files in $logs):"
  for f in "${reports[@]}"; do
    echo "=== $f"
    head -c 16000 "$f"
  done
  status=1
fi
exit $status
