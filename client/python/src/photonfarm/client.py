"""Client: one coordinator, its jobs and blobs."""

from __future__ import annotations

import hashlib
import os
import pathlib
import secrets
import tempfile
from collections.abc import Iterator, Mapping
from typing import Any, BinaryIO, Optional

import grpc
from renderfarm.v1 import blob_pb2, blob_pb2_grpc, job_pb2, job_pb2_grpc

from . import contract, scenes
from .connection import DEFAULT_ADDRESS, TLS, open_channel
from .errors import FarmError, from_rpc
from .exr import Image, read_image
from .jobs import JobEvent, Report, state_name

FINAL_IMAGE = "image.exr"
"""The artifact name of a job's final multi-layer EXR."""


class Client:
    """A connection to a coordinator, with the farm CLI's options:

    address   HOST:PORT; default $FARM_COORDINATOR, else localhost:7070
    token     the client token sent with every call; default $FARM_TOKEN ("": none)
    tls       see connection.TLS: default $FARM_TLS_CA if set (a CA file), else plaintext
    allow_plaintext_token   send the token without TLS to an address that is not loopback
              (the CLI's --insecure); refused otherwise
    timeout   seconds each call but watch and downloads may take

    The connection is made on the first call. Every failure raises FarmError. Use it as a
    context manager, or call close().
    """

    def __init__(self, address: Optional[str] = None, *, token: Optional[str] = None, tls: TLS = None,
                 allow_plaintext_token: bool = False, timeout: float = 60.0):
        self.address = address or os.environ.get("FARM_COORDINATOR") or DEFAULT_ADDRESS
        if token is None:
            token = os.environ.get("FARM_TOKEN", "")
        self.timeout = timeout
        self._channel = open_channel(self.address, token, tls, allow_plaintext_token)
        self.jobs = job_pb2_grpc.JobServiceStub(self._channel)
        """The raw JobService stub, for calls the SDK does not wrap."""
        self.blobs = blob_pb2_grpc.BlobServiceStub(self._channel)
        """The raw BlobService stub."""

    def close(self) -> None:
        self._channel.close()

    def __enter__(self) -> "Client":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def _fail(self, what: str, err: grpc.RpcError) -> FarmError:
        return from_rpc(what, err, self.address)

    def submit(self, scene: scenes.SceneSource, assets: Optional[Mapping[str, scenes.AssetSource]] = None, *,
               asset_root: Optional[str | os.PathLike] = None, priority: int = 0,
               request_id: Optional[str] = None) -> job_pb2.Job:
        """Uploads the files the scene names and submits it as a new job; returns the job.

        scene is a scene file's path, a dict of its JSON form or a Scene message. Paths in
        it are relative to the scene file's folder (for a dict or a message, asset_root,
        else the working folder) and must lie within asset_root (default that folder),
        symbolic links resolved. assets maps a path as the scene writes it to its content instead, bytes
        or another file: {"meshes/ball.obj": obj_text.encode()}. Files the store has
        already are not sent again. priority is in [-1000, 1000], higher first.
        request_id names the submission (default: a random one) so that a retried submit
        makes one job. A bad scene or file raises FarmError INVALID_ARGUMENT naming the
        field ("shapes[3].mesh.path").
        """
        root = pathlib.Path(asset_root) if asset_root is not None else None
        sc, base = scenes.read_scene(scene, root)
        root = root or base
        for asset in scenes.find_assets(sc, base, root, assets or {}):
            self._upload(asset)
        request = job_pb2.SubmitJobRequest(scene=sc, priority=priority,
                                           request_id=request_id or secrets.token_hex(16))
        try:
            return self.jobs.SubmitJob(request, timeout=self.timeout).job
        except grpc.RpcError as e:
            raise self._fail("submit job", e) from None

    def _call(self, what: str, rpc: grpc.UnaryUnaryMultiCallable, request: object) -> Any:
        """One unary call with the client's timeout; a failure raises FarmError naming what."""
        try:
            return rpc(request, timeout=self.timeout)
        except grpc.RpcError as e:
            raise self._fail(what, e) from None

    def get_job(self, job_id: str) -> job_pb2.Job:
        return self._call("get job", self.jobs.GetJob, job_pb2.GetJobRequest(job_id=job_id)).job

    def cancel(self, job_id: str) -> job_pb2.Job:
        """Cancels a job that has not ended; returns it, CANCELLED. FAILED_PRECONDITION if
        it has ended."""
        return self._call("cancel job", self.jobs.CancelJob, job_pb2.CancelJobRequest(job_id=job_id)).job

    def requeue(self, job_id: str) -> job_pb2.Job:
        """Reopens a FAILED or CANCELLED job where it stopped: its tasks that did not succeed
        are queued again. FAILED_PRECONDITION for a job that succeeded or has not ended."""
        return self._call("requeue job", self.jobs.RequeueJob, job_pb2.RequeueJobRequest(job_id=job_id)).job

    def retry(self, task_id: str) -> job_pb2.Job:
        """Queues a FAILED task again and reopens its job; returns the job.
        FAILED_PRECONDITION for a task that has not failed."""
        return self._call("retry task", self.jobs.RetryTask, job_pb2.RetryTaskRequest(task_id=task_id)).job

    def delete(self, job_id: str) -> job_pb2.Job:
        """Deletes a job, cancelling it first if it has not ended; returns it as it was
        deleted. Its outputs go with the coordinator's blob collection."""
        return self._call("delete job", self.jobs.DeleteJob, job_pb2.DeleteJobRequest(job_id=job_id)).job

    def watch(self, job_id: str) -> Iterator[JobEvent]:
        """Yields the job's events, the first a snapshot of it, and stops after the one that
        shows it ended. Raises FarmError UNAVAILABLE if the stream ends before the job."""
        stream = self.jobs.WatchJob(job_pb2.WatchJobRequest(job_id=job_id))
        try:
            for response in stream:
                event = JobEvent.from_pb(response)
                yield event
                if event.ended:
                    return
        except grpc.RpcError as e:
            raise self._fail("watch job", e) from None
        finally:
            stream.cancel()
        raise FarmError(grpc.StatusCode.UNAVAILABLE, f"watch job {job_id}: the event stream ended before the job did")

    def fetch(self, job_id: str) -> Image:
        """Downloads a succeeded job's final EXR and returns its layers as NumPy arrays
        (exr.Image: image.layers["indirect"] is an array of (height, width, 3))."""
        job = self.get_job(job_id)
        if job.state != job_pb2.JOB_STATE_SUCCEEDED:
            reason = f": {job.error}" if job.error else ""
            raise FarmError(grpc.StatusCode.FAILED_PRECONDITION,
                            f"job {job_id} has no outputs: it is {state_name(job.state)}{reason}")
        artifact = next((a for a in job.outputs if a.name == FINAL_IMAGE), None)
        if artifact is None:
            raise FarmError(grpc.StatusCode.DATA_LOSS, f"job {job_id} succeeded without {FINAL_IMAGE}")
        with tempfile.TemporaryDirectory(prefix="photonfarm-") as tmp:
            path = pathlib.Path(tmp) / FINAL_IMAGE
            with open(path, "wb") as f:
                self.download(artifact.digest, f)
            return read_image(path)

    def report(self, job_id: str) -> Report:
        """The job's rounds: run time, photons, samples and error, as `farm report` shows."""
        return Report.from_pb(self.get_job(job_id))

    def _upload(self, asset: scenes.Asset) -> None:
        """Stores the asset in the blob store, unless it is there intact: a header, then
        chunks of the contract's size. The coordinator checks size and digest."""
        try:
            self.blobs.GetBlobInfo(blob_pb2.GetBlobInfoRequest(digest=asset.digest), timeout=self.timeout)
            return
        except grpc.RpcError as e:
            if e.code() not in (grpc.StatusCode.NOT_FOUND, grpc.StatusCode.DATA_LOSS):
                raise self._fail("blob info", e) from None

        def parts() -> Iterator[blob_pb2.UploadBlobRequest]:
            yield blob_pb2.UploadBlobRequest(header=blob_pb2.BlobHeader(size_bytes=asset.size, digest=asset.digest))
            chunk = contract.RPC.max_upload_chunk_bytes
            if isinstance(asset.content, bytes):
                for i in range(0, asset.size, chunk):
                    yield blob_pb2.UploadBlobRequest(chunk=asset.content[i:i + chunk])
                return
            with scenes.open_regular(asset.content, contract.SCENE.max_asset_bytes, asset.written, asset.field) as f:
                while data := f.read(chunk):
                    yield blob_pb2.UploadBlobRequest(chunk=data)

        try:
            self.blobs.UploadBlob(parts(), timeout=self.timeout)
        except grpc.RpcError as e:
            err = self._fail("upload blob", e)
            raise FarmError(err.code, f"{asset.written}: {err.message}", field=asset.field, hint=err.hint) from None

    def download(self, digest: str, out: BinaryIO) -> int:
        """Streams the blob digest into out, checking its size and digest; returns its size."""
        h = hashlib.sha256()
        n, want = 0, -1
        try:
            for msg in self.blobs.DownloadBlob(blob_pb2.DownloadBlobRequest(digest=digest)):
                if want < 0:
                    want = msg.size_bytes
                h.update(msg.chunk)
                out.write(msg.chunk)
                n += len(msg.chunk)
        except grpc.RpcError as e:
            raise self._fail(f"download blob {digest}", e) from None
        got = "sha256:" + h.hexdigest()
        if n != max(want, 0) or got != digest:
            raise FarmError(grpc.StatusCode.DATA_LOSS,
                            f"download blob {digest}: got {n} bytes of digest {got}, announced {want}")
        return n
