"""Errors of the Python client."""

from __future__ import annotations

import grpc


class PartitaError(Exception):
    """A failed call or a job that did not finish. `code` is the gRPC status code name
    ("INVALID_ARGUMENT", "NOT_FOUND", ...) when the server answered, else None."""

    def __init__(self, message: str, code: str | None = None):
        super().__init__(f"{message} ({code})" if code else message)
        self.message = message
        self.code = code


def from_rpc_error(error: grpc.RpcError, what: str, address: str = "") -> PartitaError:
    code = error.code() if hasattr(error, "code") else None
    details = (error.details() if hasattr(error, "details") else None) or str(error)
    details = " ".join(details.split())
    if code == grpc.StatusCode.UNAVAILABLE:
        details = f"cannot reach the server{' at ' + address if address else ''}: {details}"
    return PartitaError(f"{what}: {details}" if what else details, code.name if code else None)
