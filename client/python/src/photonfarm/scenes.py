"""Reading a scene (a file, a dict or a Scene message) and finding the files it names.

A scene names meshes, textures and its reference image by path; the coordinator knows
them only by digest, so the client uploads each file and sets its digest, keeping the
path as written so that the coordinator's messages name the file as the user knows it
(as the farm CLI does). The messages that name a file are found from the contract: every
message with a string field path beside a field digest whose (rule) says digest, so a new
kind of asset in scene.proto needs nothing here.
"""

from __future__ import annotations

import dataclasses
import hashlib
import os
import pathlib
import stat
from collections.abc import Iterator, Mapping
from typing import BinaryIO, Optional, Union

from google.protobuf import json_format
from google.protobuf.message import Message
from renderfarm.v1 import rules_pb2, scene_pb2

from . import contract
from .errors import invalid

SceneSource = Union[str, os.PathLike, Mapping, scene_pb2.Scene]
"""A scene file's path, a dict in the scene file's JSON form, or a Scene message."""

AssetSource = Union[str, os.PathLike, bytes]
"""Where a file the scene names comes from: another file, or its bytes."""

READ_CHUNK = 1 << 20


def read_scene(source: SceneSource, asset_root: Optional[pathlib.Path]) -> tuple[scene_pb2.Scene, pathlib.Path]:
    """Returns the scene (a copy the caller may change) and the folder its relative paths
    start from: the scene file's folder; for a dict or a message, asset_root if given,
    else the working folder."""
    base = asset_root if asset_root is not None else pathlib.Path.cwd()
    if isinstance(source, scene_pb2.Scene):
        sc = scene_pb2.Scene()
        sc.CopyFrom(source)
        return sc, base
    if isinstance(source, Mapping):
        try:
            return json_format.ParseDict(source, scene_pb2.Scene()), base
        except json_format.ParseError as e:
            raise invalid("", f"scene: {e}") from e
    path = pathlib.Path(source)
    text = read_small_file(path, contract.RPC.max_message_bytes, str(source))
    try:
        return json_format.Parse(text, scene_pb2.Scene()), path.parent
    except json_format.ParseError as e:
        raise invalid("", f"{source}: {e}") from e


def file_messages(msg: Message, prefix: str = "") -> Iterator[tuple[str, Message]]:
    """Yields (field path, message) for every message within msg, msg included, that names
    a file (path and digest fields), depth first in field order: ("shapes[3].mesh", ...)."""
    fields = msg.DESCRIPTOR.fields_by_name
    if "path" in fields and "digest" in fields and \
            fields["digest"].GetOptions().Extensions[rules_pb2.rule].digest:
        yield prefix, msg
    for fd, value in msg.ListFields():
        if fd.message_type is None:
            continue
        name = f"{prefix}.{fd.name}" if prefix else fd.name
        if fd.is_repeated:
            for i, item in enumerate(value):
                yield from file_messages(item, f"{name}[{i}]")
        else:
            yield from file_messages(value, name)


@dataclasses.dataclass(frozen=True)
class Asset:
    """One file a scene names, found and hashed, ready to upload."""

    field: str  # the path field that names it: "shapes[3].mesh.path"
    written: str  # the path as the scene writes it
    digest: str  # "sha256:..."
    size: int
    content: Union[pathlib.Path, bytes]


def find_assets(sc: scene_pb2.Scene, base: pathlib.Path, root: pathlib.Path,
                given: Mapping[str, AssetSource]) -> list[Asset]:
    """Finds, checks and hashes every file sc names by path and sets its digest. A path
    that is a key of given takes its content from there (bytes, or a file anywhere);
    others are files relative to base that must lie within root, symbolic links resolved.
    Each is a regular file of at most the contract's max_asset_bytes. Errors are
    FarmErrors naming the field."""
    root_abs = pathlib.Path(os.path.abspath(root))
    root_real = root_abs.resolve()
    found: dict[str, Asset] = {}
    for prefix, msg in file_messages(sc):
        written = msg.path
        if not written:
            continue
        field = f"{prefix}.path"
        if written in given:
            asset = _given_asset(field, written, given[written])
        else:
            asset = _file_asset(field, written, _resolve(field, written, base, root_abs, root_real))
        found.setdefault(asset.digest, asset)  # the same content is uploaded once
        if msg.digest and msg.digest != asset.digest:
            raise invalid(f"{prefix}.digest", f"is {msg.digest} but the file at path {written!r} "
                          f"has digest {asset.digest}; set only one of path and digest")
        msg.digest = asset.digest
    return list(found.values())


def _within(root: pathlib.Path, p: pathlib.Path) -> bool:
    return p == root or root in p.parents


def _resolve(field: str, written: str, base: pathlib.Path, root_abs: pathlib.Path,
             root_real: pathlib.Path) -> pathlib.Path:
    """The file a scene names as written, symbolic links resolved; refused when it leaves
    the asset root as written or once links are followed."""
    p = pathlib.Path(os.path.abspath(base / written))
    if not _within(root_abs, p) and not _within(root_real, p):
        raise invalid(field, f"{written!r} is outside the asset root {root_abs} (it is {p}); move "
                      "the file into the root or choose a wider root (asset_root=...)")
    real = p.resolve()
    if not _within(root_real, real):
        raise invalid(field, f"{written!r} leads through a symbolic link to {real}, outside the "
                      f"asset root {root_real}; move the file into the root or choose a wider "
                      "root (asset_root=...)")
    return real


def _given_asset(field: str, written: str, source: AssetSource) -> Asset:
    if isinstance(source, bytes):
        if len(source) > contract.SCENE.max_asset_bytes:
            raise invalid(field, f"{written}: {len(source)} bytes, more than the limit of "
                          f"{contract.SCENE.max_asset_bytes}")
        return Asset(field, written, "sha256:" + hashlib.sha256(source).hexdigest(), len(source), source)
    return _file_asset(field, written, pathlib.Path(source))


def _file_asset(field: str, written: str, path: pathlib.Path) -> Asset:
    h = hashlib.sha256()
    size = 0
    with open_regular(path, contract.SCENE.max_asset_bytes, written, field) as f:
        while chunk := f.read(READ_CHUNK):
            h.update(chunk)
            size += len(chunk)
    return Asset(field, written, "sha256:" + h.hexdigest(), size, path)


def open_regular(path: pathlib.Path, limit: int, name: str, field: str = "") -> BinaryIO:
    """Opens path for reading if it is a regular file of at most limit bytes (a device or
    a pipe could be read for ever). It opens without blocking, as a pipe's open would wait
    for a writer, and checks what it opened. Errors name the file as name, and field."""
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
    except OSError as e:
        raise invalid(field, f"open {name}: {e.strerror}") from e
    f = os.fdopen(fd, "rb")
    st = os.fstat(fd)
    if not stat.S_ISREG(st.st_mode):
        f.close()
        raise invalid(field, f"read {name}: not a regular file (a folder, a device or a pipe)")
    if st.st_size > limit:
        f.close()
        raise invalid(field, f"read {name}: {st.st_size} bytes, more than the limit of {limit}")
    return f


def read_small_file(path: pathlib.Path, limit: int, name: str) -> str:
    with open_regular(path, limit, name) as f:
        data = f.read()
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as e:
        raise invalid("", f"{name}: not UTF-8 text: {e}") from e
