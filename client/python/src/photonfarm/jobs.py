"""Typed views of what the coordinator says about jobs: watch events and round reports.
The messages themselves (Job, Task) are the generated renderfarm.v1.job_pb2 types."""

from __future__ import annotations

import dataclasses
import datetime
from typing import Optional

from renderfarm.v1 import job_pb2

ENDED_STATES = frozenset({job_pb2.JOB_STATE_SUCCEEDED, job_pb2.JOB_STATE_FAILED, job_pb2.JOB_STATE_CANCELLED})


def state_name(state: int) -> str:
    """A job state for people: "queued", "running", "succeeded", ..."""
    return job_pb2.JobState.Name(state).removeprefix("JOB_STATE_").lower()


@dataclasses.dataclass(frozen=True)
class JobEvent:
    """One event of a job's watch stream.

    kind is job_pb2.JOB_EVENT_KIND_SNAPSHOT (the first event: the job as it is),
    JOB_EVENT_KIND_STATE_CHANGED (job is the job after the change),
    JOB_EVENT_KIND_TASK_UPDATED (task is the task after the update; job, when set, the
    job with its progress) or JOB_EVENT_KIND_JOB_UPDATED (job is the job after a change of
    neither its state nor a task: its blocklist or its priority).
    """

    kind: int
    time: datetime.datetime
    job: Optional[job_pb2.Job]
    task: Optional[job_pb2.Task]

    @classmethod
    def from_pb(cls, ev: job_pb2.WatchJobResponse) -> "JobEvent":
        return cls(kind=ev.kind, time=ev.time.ToDatetime(tzinfo=datetime.timezone.utc),
                   job=ev.job if ev.HasField("job") else None,
                   task=ev.task if ev.HasField("task") else None)

    @property
    def kind_name(self) -> str:
        """"snapshot", "state_changed" or "task_updated"."""
        return job_pb2.JobEventKind.Name(self.kind).removeprefix("JOB_EVENT_KIND_").lower()

    @property
    def ended(self) -> bool:
        """Whether the event shows the job ended (succeeded, failed or cancelled)."""
        return self.job is not None and self.job.state in ENDED_STATES


@dataclasses.dataclass(frozen=True)
class Round:
    """One progressive round's figures (job.proto's RoundReport). error_estimate (with its
    bias part and 95% interval, error_estimate_low to error_estimate_high) and
    reference_rmse are None when the round did not measure them."""

    round: int
    elapsed_seconds: float
    photons: int
    samples_per_pixel: int
    error_estimate: Optional[float]
    reference_rmse: Optional[float]
    layer_reference_rmse: dict[str, float]
    error_estimate_bias: Optional[float] = None
    error_estimate_low: Optional[float] = None
    error_estimate_high: Optional[float] = None

    @classmethod
    def from_pb(cls, r: job_pb2.RoundReport) -> "Round":
        return cls(round=r.round, elapsed_seconds=r.elapsed_seconds, photons=r.photons,
                   samples_per_pixel=r.samples_per_pixel,
                   error_estimate=r.error_estimate if r.HasField("error_estimate") else None,
                   reference_rmse=r.reference_rmse if r.HasField("reference_rmse") else None,
                   layer_reference_rmse=dict(r.layer_reference_rmse),
                   **{f: getattr(r, f) if r.HasField(f) else None
                      for f in ("error_estimate_bias", "error_estimate_low", "error_estimate_high")})


@dataclasses.dataclass(frozen=True)
class Report:
    """A job's error against run time, round by round, as `farm report` prints it."""

    job_id: str
    name: str
    state: str
    rounds: list[Round]

    @classmethod
    def from_pb(cls, job: job_pb2.Job) -> "Report":
        return cls(job_id=job.id, name=job.display_name, state=state_name(job.state),
                   rounds=[Round.from_pb(r) for r in job.rounds])
