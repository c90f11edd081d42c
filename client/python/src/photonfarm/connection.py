"""The gRPC channel to a coordinator, with the farm CLI's token and TLS rules: a token is
sent as "authorization: Bearer TOKEN" on every call, and without TLS only to a loopback
address unless the caller allows plaintext (the CLI's --insecure)."""

from __future__ import annotations

import collections
import ipaddress
import os
import pathlib
from typing import Optional, Union

import grpc

from . import contract
from .errors import FarmError

DEFAULT_ADDRESS = "localhost:7070"

TLS = Union[None, bool, str, os.PathLike]
"""None: $FARM_TLS_CA if set, else plaintext; False: plaintext; True: TLS trusting the
system's roots; a path: TLS trusting the CA certificates in that PEM file."""


_LIST_OF_LITERALS = ("several addresses must be IP literals, all IPv4 or all IPv6 (gRPC's list targets take "
                     "no names); for names, give one DNS name that resolves to every coordinator")


def _ip_family(host_port: str) -> Optional[int]:
    """4 or 6 for an IP literal's HOST:PORT (IPv6 bracketed), None for a name."""
    host = host_port.rpartition(":")[0]
    if host.startswith("[") and host.endswith("]"):
        host = host[1:-1]
    try:
        return ipaddress.ip_address(host).version
    except ValueError:
        return None


def replica_target(address: str) -> tuple[str, list[tuple[str, object]]]:
    """The gRPC target and channel options for address: one HOST:PORT (a name resolves to
    every address it has) as it is, or coordinator replicas on one Redis as a comma list
    of IP literals of one family, "ipv4:A,B" with calls spread over the replicas that
    answer (round_robin), the rule farm-worker follows (worker/daemon/coordinator_address.h);
    with TLS every replica is checked against the first one's address."""
    parts = address.split(",")
    if len(parts) == 1:
        return address, []
    families = set()
    for part in parts:
        host, _, port = part.rpartition(":")
        if not host or not port.isdigit() or not 1 <= int(port) <= 65535:
            raise FarmError(grpc.StatusCode.INVALID_ARGUMENT, f'coordinator address "{part}" in "{address}" is not HOST:PORT')
        families.add(_ip_family(part))
    if len(set(parts)) != len(parts):
        raise FarmError(grpc.StatusCode.INVALID_ARGUMENT, f'"{address}" lists an address twice')
    if None in families or len(families) != 1:
        raise FarmError(grpc.StatusCode.INVALID_ARGUMENT, f'"{address}": {_LIST_OF_LITERALS}')
    # One authority for every connection, the first replica's: with TLS, the replicas'
    # certificate must name it (gRPC checks every connection against the channel's authority).
    return f"ipv{families.pop()}:{address}", [("grpc.lb_policy_name", "round_robin"),
                                              ("grpc.default_authority", parts[0])]


def is_loopback(address: str) -> bool:
    """Whether the gRPC target ("host:port", "dns:///host:port", "unix:path", or a comma list
    of replicas, each of them) names this machine without leaving it: localhost, a loopback
    IP or a unix socket. Names are not resolved."""
    if "," in address:
        return all(is_loopback(a) for a in address.split(","))
    if address.startswith(("unix:", "unix-abstract:")):
        return True
    for scheme in ("dns:///", "passthrough:///"):
        address = address.removeprefix(scheme)
    host = address
    if address.startswith("["):
        host = address[1:].partition("]")[0]
    elif address.count(":") == 1:
        host = address.partition(":")[0]
    if host.lower() == "localhost" or host.lower().endswith(".localhost"):
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


class _CallDetails(collections.namedtuple("_CallDetails", ("method", "timeout", "metadata", "credentials",
                                                           "wait_for_ready", "compression")),
                   grpc.ClientCallDetails):
    pass


class _BearerToken(grpc.UnaryUnaryClientInterceptor, grpc.UnaryStreamClientInterceptor,
                   grpc.StreamUnaryClientInterceptor, grpc.StreamStreamClientInterceptor):
    """Adds the token to every call's metadata, so the raw stubs carry it too."""

    def __init__(self, token: str):
        self._entry = ("authorization", "Bearer " + token)

    def _with_token(self, d: grpc.ClientCallDetails) -> _CallDetails:
        metadata = list(d.metadata or []) + [self._entry]
        return _CallDetails(d.method, d.timeout, metadata, d.credentials,
                            getattr(d, "wait_for_ready", None), getattr(d, "compression", None))

    def intercept_unary_unary(self, continuation, details, request):
        return continuation(self._with_token(details), request)

    def intercept_unary_stream(self, continuation, details, request):
        return continuation(self._with_token(details), request)

    def intercept_stream_unary(self, continuation, details, request_iterator):
        return continuation(self._with_token(details), request_iterator)

    def intercept_stream_stream(self, continuation, details, request_iterator):
        return continuation(self._with_token(details), request_iterator)


def open_channel(address: str, token: str, tls: TLS, allow_plaintext_token: bool) -> grpc.Channel:
    """A channel to address that allows the contract's largest messages (gRPC's default
    would refuse answers over 4 MiB), secured as tls says, sending token if not empty."""
    if tls is None:
        tls = os.environ.get("FARM_TLS_CA") or False
    if token and tls is False and not allow_plaintext_token and not is_loopback(address):
        raise FarmError(grpc.StatusCode.FAILED_PRECONDITION,
                        f"refusing to send the token without TLS to {address}, which is not loopback",
                        hint="pass tls=CA_FILE, or allow_plaintext_token=True on a trusted network")
    target, options = replica_target(address)
    limit = contract.RPC.max_message_bytes
    options += [("grpc.max_receive_message_length", limit), ("grpc.max_send_message_length", limit)]
    if tls is False:
        channel = grpc.insecure_channel(target, options=options)
    else:
        roots: Optional[bytes] = None
        if tls is not True:
            try:
                roots = pathlib.Path(tls).read_bytes()
            except OSError as e:
                raise FarmError(grpc.StatusCode.INVALID_ARGUMENT, f"TLS CA file {tls}: {e.strerror}") from e
            if b"-----BEGIN CERTIFICATE-----" not in roots:
                raise FarmError(grpc.StatusCode.INVALID_ARGUMENT, f"TLS CA file {tls}: no PEM certificate in it")
        channel = grpc.secure_channel(target, grpc.ssl_channel_credentials(root_certificates=roots), options=options)
    if token:
        channel = grpc.intercept_channel(channel, _BearerToken(token))
    return channel
