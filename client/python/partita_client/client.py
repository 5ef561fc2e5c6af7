"""The Partita client: submit jobs, watch them, get results as numpy arrays."""

from __future__ import annotations

import json
import os
import time
from pathlib import Path
from typing import Dict, Iterator, List, Optional, Sequence, Union

import grpc
import numpy as np

from . import exr
from ._stubs import pb2, pb2_grpc
from .algorithms import Algorithm, value_to_proto
from .errors import PartitaError, from_rpc_error
from .models import Job, PreviewEvent, StateEvent, event_from_proto, TERMINAL_STATES
from .scene import add_environment_image, scene_source, upload_chunks

# submit() keywords that are not declared parameters: the job's algorithm, budget, queue place,
# label and an environment image file (uploaded with the scene). Every other keyword is a
# declared parameter of the algorithm (Client.algorithms()), sent by name in JobSpec.parameters;
# '-' may stand for '_' (max-depth == max_depth).
_BUDGETS = {
    "spp": pb2.BUDGET_KIND_SAMPLES_PER_PIXEL,
    "mpp": pb2.BUDGET_KIND_MUTATIONS_PER_PIXEL,
    "seconds": pb2.BUDGET_KIND_SECONDS,
}
_JOB_FIELDS = ("algorithm", "priority", "label", "environment")
# The names of the typed JobSpec fields, which older code passed: each is the parameter named
# on the right.
_OLD_NAMES = {"preview_interval_seconds": "preview_interval", "max_type_layers": "layers",
              "environment_rotation_degrees": "environment_rotation",
              "bootstrap_samples": "bootstrap"}
JOB_PARAMETERS = tuple(sorted(_JOB_FIELDS + tuple(_BUDGETS)))

_RESULT_KINDS = {
    "exr": pb2.RESULT_KIND_EXR,
    "png": pb2.RESULT_KIND_PNG,
    "metadata": pb2.RESULT_KIND_METADATA,
}


def _loopback_for_localhost(address: str) -> str:
    """"localhost:PORT" -> "127.0.0.1:PORT" (RFC 6761). gRPC's c-ares resolver asks DNS servers
    for "localhost" when /etc/hosts lacks it (a minimal container) and fails where there are
    none; partitad listens on 127.0.0.1 by default."""
    prefix = "localhost:"
    return "127.0.0.1:" + address[len(prefix):] if address.startswith(prefix) else address


def parameter_name(name: str) -> str:
    """The declared name a keyword stands for: '-' read as '_', older names mapped."""
    name = name.replace("-", "_")
    return _OLD_NAMES.get(name, name)


def job_spec(scene, **params) -> "pb2.JobSpec":
    """The JobSpec for `scene` (a .gltf/.glb path or a scene name) and job keywords: algorithm,
    spp | mpp | seconds, priority, label, environment (an EXR/HDR image file), and any declared
    parameter of the algorithm by name (width, height, seed, max_depth, k, y, radius, epsilon,
    prepass, bootstrap, environment_color=(R, G, B), ...: Client.algorithms() lists them with
    their types, defaults and ranges). Unset ones take the server's defaults; the server checks
    every value. Raises ValueError on a value no parameter can take or two budgets."""
    spec = pb2.JobSpec()
    spec.scene.CopyFrom(scene_source(scene))
    if spec.scene.WhichOneof("source") != "scene_name":
        spec.scene_file = Path(scene).name  # listings show the file's name, not "upload"
    spec.algorithm = "pt"
    budgets = []
    for raw_name, value in params.items():
        name = parameter_name(raw_name)
        if value is None:
            continue
        if name in _BUDGETS:
            budgets.append(name)
            spec.budget.kind = _BUDGETS[name]
            spec.budget.amount = float(value)
        elif name == "priority":
            spec.priority = int(value)
        elif name == "environment":
            add_environment_image(spec, value)
        elif name in ("algorithm", "label"):
            setattr(spec, name, str(value))
        else:
            try:
                value_to_proto(value, spec.parameters[name])
            except ValueError as e:
                raise ValueError(f"{raw_name}: {e}") from None
    if len(budgets) > 1:
        raise ValueError(f"give one budget, not {' and '.join(budgets)}")
    return spec


class Client:
    """A connection to a partitad.

    address: "HOST:PORT". token: the bearer token (or token_file: a file holding it).
    tls_ca: PEM root certificate(s) file; given, the channel uses TLS.
    timeout: seconds for unary calls (streams have none).
    """

    def __init__(self, address: str, token: Optional[str] = None, *,
                 token_file: Optional[Union[str, os.PathLike]] = None,
                 tls_ca: Optional[Union[str, os.PathLike]] = None,
                 tls_server_name: Optional[str] = None, timeout: float = 60.0):
        self.address = address
        if token is None and token_file is not None:
            lines = Path(token_file).read_text().strip().splitlines()
            token = lines[0].strip() if lines else ""
            if not token:
                raise PartitaError(f"token file '{token_file}' is empty")
        self._metadata = (("authorization", f"Bearer {token}"),) if token else ()
        self.timeout = timeout
        options = [("grpc.max_receive_message_length", -1),
                   ("grpc.max_send_message_length", -1)]
        target = _loopback_for_localhost(address)
        if tls_ca is not None:
            if not tls_server_name and target != address:
                tls_server_name = "localhost"  # the name the caller dialled
            if tls_server_name:
                options.append(("grpc.ssl_target_name_override", tls_server_name))
            creds = grpc.ssl_channel_credentials(root_certificates=Path(tls_ca).read_bytes())
            self._channel = grpc.secure_channel(target, creds, options=options)
        else:
            self._channel = grpc.insecure_channel(target, options=options)
        self._stub = pb2_grpc.PartitaStub(self._channel)

    # --- plumbing -------------------------------------------------------------------------
    def close(self) -> None:
        self._channel.close()

    def __enter__(self) -> "Client":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def _call(self, method: str, request, what: str):
        try:
            return getattr(self._stub, method)(request, timeout=self.timeout,
                                               metadata=self._metadata)
        except grpc.RpcError as e:
            raise from_rpc_error(e, what, self.address) from None

    # --- jobs -----------------------------------------------------------------------------
    def submit(self, scene: Union[str, os.PathLike], **params) -> str:
        """Submits a job; returns its id. `scene`: a .gltf/.glb path (uploaded with its
        resources) or a scene name of the server's scene root. `params`: see job_spec(). A
        name the algorithm does not declare is refused before anything is sent."""
        spec = job_spec(scene, **params)
        self.check_parameters(spec.algorithm, spec.parameters.keys())
        if spec.scene.WhichOneof("source") in ("glb", "gltf"):
            spec.scene.upload_id = self.upload(spec.scene)
        return self._call("SubmitJob", pb2.SubmitJobRequest(spec=spec), "submit job").job_id

    def upload(self, scene) -> str:
        """Streams a scene to the server ahead of its jobs (UploadScene) and returns the upload
        id jobs name it by (`SceneSource.upload_id`; Client.submit does this for a file).
        `scene`: a .gltf/.glb path or a SceneSource holding an upload. The server holds one
        piece at a time; an upload no job names for the server's upload_ttl_seconds is
        removed."""
        source = scene if isinstance(scene, pb2.SceneSource) else scene_source(scene)
        # A server receiving as many uploads as it takes (--max-upload-streams) is waited for,
        # backing off to 5 s, for at most 10 minutes (the CLI's rule).
        give_up, pause = time.monotonic() + 600, 0.25
        while True:
            try:
                return self._stub.UploadScene(upload_chunks(source), timeout=3600,
                                              metadata=self._metadata).upload_id
            except grpc.RpcError as e:
                busy = (e.code() == grpc.StatusCode.RESOURCE_EXHAUSTED
                        and "--max-upload-streams" in (e.details() or ""))
                if not busy or time.monotonic() + pause > give_up:
                    raise from_rpc_error(e, "upload scene", self.address) from None
            time.sleep(pause)
            pause = min(pause * 2, 5.0)

    def check_parameters(self, algorithm: str, names) -> None:
        """Raises ValueError naming the first of `names` that `algorithm` does not declare on
        this server (nothing to check when the server does not say)."""
        offered = self.algorithms()
        if algorithm not in offered:
            return  # the server's own answer names the algorithms it has
        declared = offered[algorithm].parameters
        if not declared:
            return
        for name in names:
            if parameter_name(name) not in declared:
                raise ValueError(f"unknown parameter '{name}' for {algorithm} (its parameters: "
                                 f"{', '.join(declared)})")

    def job(self, job_id: str) -> Job:
        return Job.from_proto(self._call("GetJob", pb2.GetJobRequest(job_id=job_id),
                                         f"look up job {job_id}"))

    def jobs(self, label: Optional[str] = None, states: Sequence[str] = ()) -> List[Job]:
        """The server's jobs, optionally only those with `label` or in `states` (names)."""
        from .models import STATE_NAMES
        by_name = {v: k for k, v in STATE_NAMES.items()}
        unknown = [s for s in states if s not in by_name]
        if unknown:
            raise ValueError(f"unknown job state {unknown[0]!r} (known: {', '.join(by_name)})")
        req = pb2.ListJobsRequest(label=label or "", states=[by_name[s] for s in states])
        return [Job.from_proto(j) for j in self._call("ListJobs", req, "list jobs").jobs]

    def cancel(self, job_id: str) -> Job:
        return Job.from_proto(self._call("CancelJob", pb2.CancelJobRequest(job_id=job_id),
                                         f"cancel job {job_id}"))

    def delete(self, job_id: str) -> None:
        self._call("DeleteJob", pb2.DeleteJobRequest(job_id=job_id), f"delete job {job_id}")

    def server_info(self):
        """The server's ServerInfo message: version, threads, limits, algorithms."""
        return self._call("GetServerInfo", pb2.ServerInfoRequest(), "get server info")

    def algorithms(self) -> Dict[str, Algorithm]:
        """The server's algorithms by name, each with its budgets and declared parameters
        (type, default, range, help): `client.algorithms()["guided"].parameters["radius"]`.
        Read once per client."""
        if getattr(self, "_algorithms", None) is None:
            self._algorithms = {a.name: Algorithm.from_proto(a)
                                for a in self.server_info().algorithms}
        return self._algorithms

    def algorithm_parameters(self, algorithm: str) -> List[str]:
        """The parameters (CLI spelling: "spp", "max-depth", "y", ...) that change what
        `algorithm` renders on this server; empty when the server does not say."""
        for a in self.server_info().algorithms:
            if a.name == algorithm:
                return list(a.parameters)
        return []

    def scenes(self) -> List[str]:
        """Names of the scenes under the server's scene root."""
        return [s.name for s in self._call("ListScenes", pb2.ListScenesRequest(),
                                           "list scenes").scenes]

    # --- watching -------------------------------------------------------------------------
    def watch(self, job_id: str, previews: bool = False, raw: bool = False) -> Iterator:
        """Events of a job until it ends: StateEvent (first, and on every change),
        ProgressEvent, and with previews=True PreviewEvent (PNG per layer; with raw=True also
        float32 (H, W, 3) pixels per layer). The iterator ends when the server closes the
        stream, which it does once the job has ended."""
        req = pb2.WatchJobRequest(job_id=job_id, previews=previews or raw, raw_previews=raw)
        stream = self._stub.WatchJob(req, metadata=self._metadata)
        try:
            for e in stream:
                event = event_from_proto(e)
                if event is not None:
                    yield event
        except grpc.RpcError as e:
            raise from_rpc_error(e, f"watch job {job_id}", self.address) from None
        finally:
            stream.cancel()

    def wait(self, job_id: str, timeout: Optional[float] = None) -> Job:
        """Blocks until the job ends; returns it (done, failed or cancelled). Raises
        PartitaError(code="DEADLINE_EXCEEDED") after `timeout` seconds."""
        import time
        deadline = None if timeout is None else time.monotonic() + timeout
        last: Optional[Job] = None
        for _ in range(100):
            req = pb2.WatchJobRequest(job_id=job_id)
            remaining = None if deadline is None else max(0.0, deadline - time.monotonic())
            try:
                for e in self._stub.WatchJob(req, metadata=self._metadata, timeout=remaining):
                    if e.WhichOneof("event") == "state":
                        last = Job.from_proto(e.state)
                        if last.finished:
                            return last
            except grpc.RpcError as e:
                raise from_rpc_error(e, f"wait for job {job_id}", self.address) from None
            # The stream ended before the job did: look it up, watch again if needed.
            last = self.job(job_id)
            if last.finished:
                return last
            time.sleep(0.2)
        raise PartitaError(f"wait for job {job_id}: the server keeps ending the stream early")

    # --- results --------------------------------------------------------------------------
    def fetch(self, job_id: str, kind: str = "exr") -> bytes:
        """The bytes of a finished job's result: kind "exr", "png" or "metadata" (JSON)."""
        if kind not in _RESULT_KINDS:
            raise ValueError(f"kind must be one of {', '.join(_RESULT_KINDS)}")
        req = pb2.FetchResultRequest(job_id=job_id, kind=_RESULT_KINDS[kind])
        buf = bytearray()
        total = 0
        try:
            for chunk in self._stub.FetchResult(req, metadata=self._metadata):
                end = chunk.offset + len(chunk.data)
                if end > len(buf):
                    buf.extend(b"\0" * (end - len(buf)))
                buf[chunk.offset:end] = chunk.data
                total = chunk.total_size
        except grpc.RpcError as e:
            raise from_rpc_error(e, f"fetch the {kind} of job {job_id}", self.address) from None
        if total and len(buf) != total:
            raise PartitaError(f"fetch the {kind} of job {job_id}: got {len(buf)} of {total} bytes")
        return bytes(buf)

    def metadata(self, job_id: str) -> dict:
        """The JSON metadata of a finished job: every parameter and statistic."""
        return json.loads(self.fetch(job_id, "metadata"))

    def result(self, job_id: str, wait: bool = True) -> Dict[str, np.ndarray]:
        """The finished image as float32 (H, W, 3) arrays: "combined" first, then one per layer
        (path type, "other"), in the file's order. Decoded from the job's EXR (exr.py). With
        wait=True (default) waits for the job first; raises PartitaError unless it is done."""
        job = self.wait(job_id) if wait else self.job(job_id)
        if job.state != "done":
            why = f": {job.error}" if job.error else (f" ({job.note})" if job.note else "")
            raise PartitaError(f"job {job_id} is {job.state}{why}", "FAILED_PRECONDITION")
        return exr.read_exr(self.fetch(job_id, "exr")).layers()

    def download(self, job_id: str, exr_path: Union[str, os.PathLike]) -> Dict[str, Path]:
        """Writes the EXR to exr_path and the PNG and JSON metadata beside it."""
        exr_path = Path(exr_path)
        paths = {"exr": exr_path, "png": exr_path.with_suffix(".png"),
                 "metadata": exr_path.with_suffix(".json")}
        for kind, p in paths.items():
            data = self.fetch(job_id, kind)
            tmp = p.with_name(p.name + ".part")
            tmp.write_bytes(data)
            tmp.replace(p)
        return paths

    def render(self, scene, **params) -> Dict[str, np.ndarray]:
        """submit + result: the finished layers of a new job."""
        return self.result(self.submit(scene, **params))


__all__ = ["Client", "job_spec", "parameter_name", "JOB_PARAMETERS", "TERMINAL_STATES", "PreviewEvent", "StateEvent"]
