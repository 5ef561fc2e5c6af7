"""partita_client: the Python client of the Partita render service.

    from partita_client import Client
    c = Client("127.0.0.1:50051")
    job = c.submit("scenes/cornell/cornell.gltf", algorithm="pt", spp=16, width=160, height=120)
    for event in c.watch(job):
        print(event)
    layers = c.result(job)          # {"combined": float32 (H, W, 3), "LDE": ..., ...}

The generated gRPC stubs are found as _stubs.py says (PYTHONPATH or $PARTITA_PYTHON_STUBS).
"""

from .client import Client, JOB_PARAMETERS, job_spec
from .daemon import LocalDaemon, find_partitad
from .errors import PartitaError
from .exr import ExrImage, read_exr
from .models import (Job, PartitionStats, PreviewEvent, PreviewLayer, Progress, ProgressEvent,
                     StateEvent, TERMINAL_STATES)
from .metrics import rmse, rel_mse

__all__ = [
    "Client", "JOB_PARAMETERS", "job_spec", "LocalDaemon", "find_partitad", "PartitaError",
    "ExrImage", "read_exr", "Job", "PartitionStats", "PreviewEvent", "PreviewLayer", "Progress",
    "ProgressEvent", "StateEvent", "TERMINAL_STATES", "rmse", "rel_mse",
]
