"""FarmError: what a failed call raises, with the gRPC status, the field at fault and a
hint of what to do."""

from __future__ import annotations

from typing import Optional

import grpc
from google.rpc import error_details_pb2
from grpc_status import rpc_status


class FarmError(Exception):
    """A failed call or refused input.

    code is the gRPC status (grpc.StatusCode.INVALID_ARGUMENT for a bad scene or asset,
    UNAVAILABLE when no coordinator answers, UNAUTHENTICATED without a valid token, ...),
    field the protobuf path of the field at fault ("shapes[3].mesh.path") when known,
    message what is wrong, and hint what to do about it, when there is something to do.
    str() gives "field: message (hint)".
    """

    def __init__(self, code: grpc.StatusCode, message: str, field: str = "", hint: str = ""):
        self.code = code
        self.field = field
        self.message = message
        self.hint = hint
        text = f"{field}: {message}" if field else message
        super().__init__(f"{text} ({hint})" if hint else text)


def invalid(field: str, message: str) -> FarmError:
    """Input the caller must fix (a scene, one of its files)."""
    return FarmError(grpc.StatusCode.INVALID_ARGUMENT, message, field=field)


def hint_for(code: grpc.StatusCode, address: str) -> str:
    """What to run or pass about a failure that is not about the input."""
    if code == grpc.StatusCode.UNAVAILABLE:
        return (f"is a coordinator running at {address}? start one with `farm coordinator`, "
                "or pass Client(address) or set $FARM_COORDINATOR")
    if code == grpc.StatusCode.UNAUTHENTICATED:
        return "give a client token: Client(address, token=...) or $FARM_TOKEN"
    if code == grpc.StatusCode.PERMISSION_DENIED:
        return "the token is not a client token of this coordinator"
    return ""


def from_rpc(what: str, err: grpc.RpcError, address: str) -> FarmError:
    """Turns a failed call into a FarmError: the field of the status's BadRequest detail,
    as the coordinator sends for invalid input, and a hint. what names the call ("submit
    job"), for failures that are not the caller's input."""
    code: grpc.StatusCode = err.code()
    message: str = err.details() or code.name
    violation = _field_violation(err)
    if violation:
        field, description = violation
        return FarmError(code, description.removeprefix(field + ": "), field=field)
    if code not in (grpc.StatusCode.INVALID_ARGUMENT, grpc.StatusCode.NOT_FOUND,
                    grpc.StatusCode.FAILED_PRECONDITION, grpc.StatusCode.RESOURCE_EXHAUSTED):
        message = f"{what}: {code.name}: {message}"
    return FarmError(code, message, hint=hint_for(code, address))


def _field_violation(err: grpc.RpcError) -> Optional[tuple[str, str]]:
    """The first field violation of a BadRequest detail, if the status carries one."""
    status = rpc_status.from_call(err)
    if status is None:
        return None
    for detail in status.details:
        bad = error_details_pb2.BadRequest()
        if detail.Unpack(bad) and bad.field_violations:
            v = bad.field_violations[0]
            return v.field, v.description
    return None
