#!/usr/bin/env bash
# Install the Debian packages of scripts/packages.txt and scripts/packages-test.txt that are
# missing, then try the optional ones of scripts/packages-slurm.txt (without them the Slurm tests
# skip, saying why).
# Idempotent and quick when everything is already there (dpkg queries, no apt call).
set -eu
here=$(cd "$(dirname "$0")" && pwd)

# The packages of list file $1 that are not installed.
missing_of() {
  local pkg status
  grep -vE '^\s*(#|$)' "$1" | while read -r pkg; do
    status=$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)
    [ "$status" = "install ok installed" ] || echo "$pkg"
  done
}

mapfile -t required < <(missing_of "$here/packages.txt"; missing_of "$here/packages-test.txt")
mapfile -t optional < <(missing_of "$here/packages-slurm.txt")
# A failed optional install is not retried on every build (remove the marker to retry).
optional_failed=/var/tmp/partita-slurm-packages-failed
[ -e "$optional_failed" ] && optional=()
[ ${#required[@]} -eq 0 ] && [ ${#optional[@]} -eq 0 ] && exit 0

SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
# Packages with daemons (munge, slurmd) must not start them on install: the tests start their
# own. Where no policy says so (a fresh container), one is put in place for the install.
policy=/usr/sbin/policy-rc.d
if [ ! -e "$policy" ]; then
  printf '#!/bin/sh\nexit 101\n' | $SUDO tee "$policy" >/dev/null
  $SUDO chmod 755 "$policy"
  trap '$SUDO rm -f "$policy"' EXIT
fi
if [ ${#required[@]} -gt 0 ]; then
  echo "installing missing packages: ${required[*]}"
  $SUDO apt-get install -y -qq --no-install-recommends "${required[@]}"
fi
if [ ${#optional[@]} -gt 0 ]; then
  echo "installing the Slurm test packages: ${optional[*]}"
  # munge's postinst makes its key by running a shell as the munge user, which fails where
  # that user cannot reach / (a chroot with a private root folder); with a key in place it
  # only sets the key's owner. The tests' cluster uses a key of its own.
  if [ ! -e /etc/munge/munge.key ]; then
    $SUDO mkdir -p /etc/munge
    $SUDO dd if=/dev/urandom of=/etc/munge/munge.key bs=1024 count=1 status=none
    $SUDO chmod 0400 /etc/munge/munge.key
  fi
  if ! $SUDO apt-get install -y -qq --no-install-recommends "${optional[@]}"; then
    # Leave dpkg clean (a half-configured package would fail every later install).
    $SUDO dpkg --purge --force-remove-reinstreq "${optional[@]}" >/dev/null 2>&1 || true
    $SUDO touch "$optional_failed" 2>/dev/null || true
    echo "warning: the Slurm packages could not be installed here; the Slurm tests will skip" >&2
  fi
fi
