"""LocalDaemon: a private partitad for scripts and tests, like the CLI's (no --server).

    with LocalDaemon() as d:
        c = Client(d.address)

starts `partitad --listen 127.0.0.1:0 --port-file F --store T/store --scene-root R
[--threads N]` in a fresh temporary folder T, waits until the standard gRPC health check answers
SERVING, and on exit sends SIGTERM (SIGKILL after 10 s) and removes T.

partitad is found: the `partitad` argument, $PARTITA_PARTITAD, <repo>/build*/server/partitad
next to this checkout, then PATH. The scene root: the `scene_root` argument,
$PARTITA_SCENE_ROOT, <repo>/scenes; else an empty folder (only uploads work).
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import tempfile
import time
from pathlib import Path
from typing import Optional, Sequence, Union

import grpc

from .errors import PartitaError

_REPO = Path(__file__).resolve().parents[3]


def find_partitad() -> Path:
    env = os.environ.get("PARTITA_PARTITAD")
    if env:
        if not os.access(env, os.X_OK):
            raise PartitaError(f"PARTITA_PARTITAD='{env}' is not an executable file")
        return Path(env)
    for p in [_REPO / "build" / "server" / "partitad", *sorted(_REPO.glob("build*/server/partitad"))]:
        if p.is_file() and os.access(p, os.X_OK):
            return p
    found = shutil.which("partitad")
    if found:
        return Path(found)
    raise PartitaError("cannot find partitad: set PARTITA_PARTITAD or put it on PATH")


def find_scene_root() -> Optional[Path]:
    env = os.environ.get("PARTITA_SCENE_ROOT")
    if env:
        if not os.path.isdir(env):
            raise PartitaError(f"PARTITA_SCENE_ROOT='{env}' is not a folder")
        return Path(env)
    return _REPO / "scenes" if (_REPO / "scenes").is_dir() else None


def health_check(channel: grpc.Channel, timeout: float = 1.0) -> bool:
    """True when grpc.health.v1.Health/Check for the whole server answers SERVING. The request
    (service "") encodes as no bytes; the response is field 1, a varint: 08 01 is SERVING."""
    check = channel.unary_unary("/grpc.health.v1.Health/Check",
                                request_serializer=lambda b: b,
                                response_deserializer=lambda b: b)
    try:
        return check(b"", timeout=timeout) == b"\x08\x01"
    except grpc.RpcError as e:
        # A server without the health service still answered: it is up.
        return e.code() == grpc.StatusCode.UNIMPLEMENTED


class LocalDaemon:
    def __init__(self, partitad: Optional[Union[str, Path]] = None,
                 scene_root: Optional[Union[str, Path]] = None, threads: Optional[int] = None,
                 extra_args: Sequence[str] = (), start_timeout: float = 30.0,
                 store: Optional[Union[str, Path]] = None):
        self.partitad = Path(partitad) if partitad else find_partitad()
        root = Path(scene_root) if scene_root else find_scene_root()
        self.dir = Path(tempfile.mkdtemp(prefix="partita-"))
        self.store = Path(store) if store else self.dir / "store"
        self.store.mkdir(parents=True, exist_ok=True)
        if root is None:
            root = self.dir / "scenes"
            root.mkdir()
        self.scene_root = root
        self.log_path = self.dir / "partitad.log"
        port_file = self.dir / "port"
        args = [str(self.partitad), "--listen", "127.0.0.1:0", "--port-file", str(port_file),
                "--store", str(self.store), "--scene-root", str(root)]
        if threads:
            args += ["--threads", str(threads)]
        args += list(extra_args)
        self._log = open(self.log_path, "wb")
        self.process = subprocess.Popen(args, stdout=self._log, stderr=subprocess.STDOUT,
                                        stdin=subprocess.DEVNULL, start_new_session=True)
        self.address = ""
        try:
            self._wait_ready(port_file, start_timeout)
        except BaseException:
            self.stop()
            raise

    def _last_log_line(self) -> str:
        try:
            lines = [l.strip() for l in self.log_path.read_text(errors="replace").splitlines()]
        except OSError:
            return ""
        lines = [l for l in lines if l]
        return lines[-1] if lines else ""

    def _wait_ready(self, port_file: Path, timeout: float) -> None:
        deadline = time.monotonic() + timeout
        channel = None
        try:
            while True:
                code = self.process.poll()
                if code is not None:
                    raise PartitaError(f"partitad did not start (exit status {code}): "
                                       f"{self._last_log_line()}")
                if channel is None:
                    try:
                        port = int(port_file.read_text().strip() or "0")
                    except (OSError, ValueError):
                        port = 0
                    if port > 0:
                        self.address = f"127.0.0.1:{port}"
                        channel = grpc.insecure_channel(self.address)
                if channel is not None and health_check(channel):
                    return
                if time.monotonic() > deadline:
                    raise PartitaError(f"partitad did not become ready within {timeout:g} s: "
                                       f"{self._last_log_line()}")
                time.sleep(0.02)
        finally:
            if channel is not None:
                channel.close()

    def stop(self) -> None:
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGTERM)
            try:
                self.process.wait(10)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        self._log.close()
        shutil.rmtree(self.dir, ignore_errors=True)

    def __enter__(self) -> "LocalDaemon":
        return self

    def __exit__(self, *exc) -> None:
        self.stop()
