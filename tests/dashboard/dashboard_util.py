"""Shared by the dashboard tests: a real partitad with --http on loopback (the Python client's
LocalDaemon, which also gives the gRPC address), and plain HTTP requests to it."""
from __future__ import annotations

import http.client
import json
import os
import tempfile
import time
from pathlib import Path

from partita_client import LocalDaemon


def artifacts_dir() -> Path:
    path = Path(os.environ.get("PARTITA_ARTIFACTS", tempfile.gettempdir())) / "dashboard"
    path.mkdir(parents=True, exist_ok=True)
    return path


class DashboardDaemon:
    """partitad with the dashboard on 127.0.0.1 (any free port)."""

    def __init__(self, extra_args=(), threads=2):
        self._dir = Path(tempfile.mkdtemp(prefix="partita-dashboard-"))
        port_file = self._dir / "http-port"
        self.daemon = LocalDaemon(threads=threads, extra_args=[
            "--http", "127.0.0.1:0", "--http-port-file", str(port_file), *extra_args])
        deadline = time.monotonic() + 10
        while not port_file.exists() and time.monotonic() < deadline:
            time.sleep(0.05)
        self.port = int(port_file.read_text().strip())
        self.base = f"http://127.0.0.1:{self.port}"

    def request(self, method, path, body=None, headers=None, timeout=30):
        """(status, headers, body bytes)."""
        connection = http.client.HTTPConnection("127.0.0.1", self.port, timeout=timeout)
        try:
            all_headers = {"X-Partita": "1"} if method not in ("GET", "HEAD") else {}
            all_headers.update(headers or {})
            if isinstance(body, (dict, list)):
                body = json.dumps(body).encode()
                all_headers.setdefault("Content-Type", "application/json")
            connection.request(method, path, body=body, headers=all_headers)
            response = connection.getresponse()
            return response.status, dict(response.getheaders()), response.read()
        finally:
            connection.close()

    def json(self, method, path, body=None, headers=None):
        status, _, data = self.request(method, path, body, headers)
        return status, (json.loads(data) if data else None)

    def stop(self):
        self.daemon.stop()


def main():
    """unittest.main, but exit 77 (ctest's SKIP_RETURN_CODE) when every test was skipped, so a
    skip shows as skipped with its reason, never as a pass."""
    import sys
    import unittest
    program = unittest.main(exit=False, verbosity=2)
    result = program.result
    if not result.wasSuccessful():
        sys.exit(1)
    if result.testsRun == len(result.skipped):
        for _, reason in result.skipped[:1]:
            print("SKIPPED:", reason)
        sys.exit(77)
    sys.exit(0)
