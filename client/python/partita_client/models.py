"""Small dataclasses for what the service returns: jobs, progress and watch events. Each keeps
the protocol message it came from in `.proto`."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Dict, List, Optional

import numpy as np

from ._stubs import pb2

STATE_NAMES = {
    pb2.JOB_STATE_QUEUED: "queued",
    pb2.JOB_STATE_LOADING: "loading",
    pb2.JOB_STATE_PREPASS: "prepass",
    pb2.JOB_STATE_RENDERING: "rendering",
    pb2.JOB_STATE_DONE: "done",
    pb2.JOB_STATE_FAILED: "failed",
    pb2.JOB_STATE_CANCELLED: "cancelled",
}
TERMINAL_STATES = ("done", "failed", "cancelled")


def state_name(state: int) -> str:
    return STATE_NAMES.get(state, "unknown")


@dataclass
class PartitionStats:
    """One of partitioned's partitions in a progress report: its type string ("complement" for
    the complement), its chains' running acceptance, b_i, P(i), the pre-pass's gamma and its
    estimator ("chains", or "per-pixel": restricted BDPT samples, no acceptance) and, where the
    algorithm chooses one per partition, its chains' image-plane move (guided: "guided" or
    "lens"; empty otherwise)."""
    type: str
    acceptance: float
    b: float
    p: float
    gamma: float = 0.0
    estimator: str = "chains"
    move: str = ""


@dataclass
class Progress:
    phase: str
    done: float
    total: float            # 0 when unknown (time budgets)
    unit: str
    rate_per_second: float
    eta_seconds: float      # < 0 when unknown
    elapsed_seconds: float
    partitions: List[PartitionStats] = field(default_factory=list)
    # Named statistics of the phase so far: mlt's "acceptance_<mutation>" and "mutations".
    values: Dict[str, float] = field(default_factory=dict)
    proto: object = field(default=None, repr=False)

    @property
    def fraction(self) -> Optional[float]:
        return min(1.0, self.done / self.total) if self.total > 0 else None

    @property
    def acceptance(self) -> Dict[str, float]:
        """The running acceptance per mutation type, {"bidirectional": 0.46, "lens": ...}
        (mlt's render phase; empty otherwise)."""
        prefix = "acceptance_"
        return {k[len(prefix):]: v for k, v in sorted(self.values.items())
                if k.startswith(prefix)}

    @classmethod
    def from_proto(cls, p) -> "Progress":
        return cls(p.phase, p.done, p.total, p.unit, p.rate_per_second, p.eta_seconds,
                   p.elapsed_seconds,
                   [PartitionStats(q.type, q.acceptance, q.b, q.p, q.gamma,
                                   q.estimator or "chains", q.move) for q in p.partitions],
                   dict(p.values), p)


@dataclass
class Job:
    id: str
    state: str              # queued, loading, prepass, rendering, done, failed, cancelled
    algorithm: str
    label: str
    scene: str              # the scene name, or "upload"
    error: str              # why it failed
    progress: Optional[Progress]
    stats: Dict[str, float]
    created_unix_ms: int
    started_unix_ms: int
    finished_unix_ms: int
    note: str = ""          # informational, never an error: e.g. why the job was re-queued
    proto: object = field(default=None, repr=False)

    @property
    def finished(self) -> bool:
        return self.state in TERMINAL_STATES

    @property
    def seconds(self) -> Optional[float]:
        """Render seconds: the "seconds" statistic, else finished - started."""
        if "seconds" in self.stats:
            return float(self.stats["seconds"])
        if self.started_unix_ms and self.finished_unix_ms >= self.started_unix_ms:
            return (self.finished_unix_ms - self.started_unix_ms) / 1000.0
        return None

    @classmethod
    def from_proto(cls, j) -> "Job":
        which = j.spec.scene.WhichOneof("source")
        upload = j.spec.scene_file or "upload"
        scene = j.spec.scene.scene_name if which == "scene_name" else (upload if which else "")
        return cls(j.id, state_name(j.state), j.spec.algorithm, j.spec.label, scene, j.error,
                   Progress.from_proto(j.progress) if j.HasField("progress") else None,
                   dict(j.stats), j.created_unix_ms, j.started_unix_ms, j.finished_unix_ms,
                   note=getattr(j, "note", ""), proto=j)


@dataclass
class PreviewLayer:
    name: str               # "combined", a path type such as "LDSDE", or "other"
    width: int
    height: int
    png: bytes
    rgb: Optional[np.ndarray]   # float32 (H, W, 3) when watched with raw=True


@dataclass
class StateEvent:
    job: Job


@dataclass
class ProgressEvent:
    progress: Progress


@dataclass
class PreviewEvent:
    sequence: int
    final: bool
    layers: Dict[str, PreviewLayer]


def event_from_proto(e):
    which = e.WhichOneof("event")
    if which == "state":
        return StateEvent(Job.from_proto(e.state))
    if which == "progress":
        return ProgressEvent(Progress.from_proto(e.progress))
    if which == "preview":
        layers = {}
        for layer in e.preview.layers:
            rgb = None
            if layer.raw_rgb_f32:
                rgb = np.frombuffer(layer.raw_rgb_f32, dtype="<f4").astype(np.float32).reshape(
                    layer.height, layer.width, 3)
            layers[layer.name] = PreviewLayer(layer.name, layer.width, layer.height, layer.png, rgb)
        return PreviewEvent(e.preview.sequence, e.preview.final, layers)
    return None
