"""Finds the generated gRPC stubs (partita/v1/partita_pb2{,_grpc}.py).

The build writes them to <build>/python (CMake target partita_python_stubs). They are found,
first match wins:
  1. on sys.path already (PYTHONPATH=<build>/python);
  2. in $PARTITA_PYTHON_STUBS (the folder that holds partita/v1/);
  3. in <repo>/build/python, then any <repo>/build*/python, next to this package's checkout.
"""

from __future__ import annotations

import importlib
import os
import sys
from pathlib import Path


def _candidates():
    env = os.environ.get("PARTITA_PYTHON_STUBS")
    if env:
        yield Path(env)
    repo = Path(__file__).resolve().parents[3]
    yield repo / "build" / "python"
    yield from sorted(repo.glob("build*/python"))


def load():
    try:
        pb2 = importlib.import_module("partita.v1.partita_pb2")
        grpc_mod = importlib.import_module("partita.v1.partita_pb2_grpc")
        return pb2, grpc_mod
    except ImportError:
        pass
    tried = []
    for folder in _candidates():
        tried.append(str(folder))
        if (folder / "partita" / "v1" / "partita_pb2.py").is_file():
            sys.path.insert(0, str(folder))
            for name in [m for m in sys.modules if m == "partita" or m.startswith("partita.")]:
                del sys.modules[name]
            pb2 = importlib.import_module("partita.v1.partita_pb2")
            grpc_mod = importlib.import_module("partita.v1.partita_pb2_grpc")
            return pb2, grpc_mod
    raise ImportError(
        "cannot find the Partita gRPC stubs (partita/v1/partita_pb2.py): build the CMake target "
        "partita_python_stubs and put <build>/python on PYTHONPATH or in PARTITA_PYTHON_STUBS "
        f"(tried: {', '.join(tried)})")


pb2, pb2_grpc = load()
