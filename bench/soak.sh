#!/bin/sh
# The soak of issue #25 item 4 (bench/soak.py says what it does and checks):
#   bench/soak.sh [--clients 50] [--jobs 10] [--restarts 20] [--seed 1] [--build build]
# needs a build of partitad and the Python stubs (make build).
exec /usr/bin/python3 "$(dirname "$0")/soak.py" "$@"
