#!/bin/sh
# Container HEALTHCHECK: asks the daemon in this container for its gRPC health status.
# With TLS (the certificate secret is present) the probe trusts PARTITA_HEALTH_CA (default: the
# server's own certificate, right for a self-signed one) and checks the name
# PARTITA_HEALTH_TLS_NAME (default localhost) in it; the token goes along when there is one.
set -eu
cert=${PARTITA_HEALTH_CA:-/run/secrets/tls_cert}
set -- --server 127.0.0.1:50051 --timeout 5
if [ -r /run/secrets/tls_cert ]; then
  set -- "$@" --tls-ca "$cert" --tls-server-name "${PARTITA_HEALTH_TLS_NAME:-localhost}"
fi
if [ -r /run/secrets/token ]; then
  set -- "$@" --token-file /run/secrets/token
fi
exec /usr/local/bin/partita-health-probe "$@"
