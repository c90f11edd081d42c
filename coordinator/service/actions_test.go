package service_test

import (
	"errors"
	"io"
	"testing"

	"google.golang.org/grpc/codes"

	"photonfarm/contract/scene/scenetest"
	pb "photonfarm/proto/renderfarm/v1"
)

// failedJob submits a job and fails its first task as bad input, which fails the job.
func (f *farm) failedJob() (job *pb.Job, worker string, failed *pb.LeaseTaskResponse) {
	f.t.Helper()
	job, worker, failed = f.leased(scenetest.Unlit(64, 64))
	f.failTask(worker, failed, pb.FailureKind_FAILURE_KIND_BAD_INPUT, "shapes[0].mesh: bad face")
	if got := f.job(job.Id); got.State != pb.JobState_JOB_STATE_FAILED {
		f.t.Fatalf("job after a bad-input failure = %v, want FAILED", got)
	}
	return job, worker, failed
}

func TestJobActionsRefuseWithTheirCodes(t *testing.T) {
	f := newFarm(t)
	running, _, l := f.leased(scenetest.Unlit(64, 64))
	queuedTask := l.Lease.TaskId
	tests := []struct {
		name  string
		call  func() error
		code  codes.Code
		field string
	}{
		{"RequeueJob without an id", func() error {
			_, err := f.jobs.RequeueJob(f.ctx, &pb.RequeueJobRequest{})
			return err
		}, codes.InvalidArgument, "job_id"},
		{"RequeueJob of an unknown job", func() error {
			_, err := f.jobs.RequeueJob(f.ctx, &pb.RequeueJobRequest{JobId: "j-nosuchjob"})
			return err
		}, codes.NotFound, ""},
		{"RequeueJob of a running job", func() error {
			_, err := f.jobs.RequeueJob(f.ctx, &pb.RequeueJobRequest{JobId: running.Id})
			return err
		}, codes.FailedPrecondition, ""},
		{"RetryTask without an id", func() error {
			_, err := f.jobs.RetryTask(f.ctx, &pb.RetryTaskRequest{})
			return err
		}, codes.InvalidArgument, "task_id"},
		{"RetryTask of a job id", func() error {
			_, err := f.jobs.RetryTask(f.ctx, &pb.RetryTaskRequest{TaskId: running.Id})
			return err
		}, codes.InvalidArgument, "task_id"},
		{"RetryTask of an unknown task", func() error {
			_, err := f.jobs.RetryTask(f.ctx, &pb.RetryTaskRequest{TaskId: running.Id + ".999"})
			return err
		}, codes.NotFound, ""},
		{"RetryTask of a leased task", func() error {
			_, err := f.jobs.RetryTask(f.ctx, &pb.RetryTaskRequest{TaskId: queuedTask})
			return err
		}, codes.FailedPrecondition, ""},
		{"DeleteJob without an id", func() error {
			_, err := f.jobs.DeleteJob(f.ctx, &pb.DeleteJobRequest{})
			return err
		}, codes.InvalidArgument, "job_id"},
		{"DeleteJob of an unknown job", func() error {
			_, err := f.jobs.DeleteJob(f.ctx, &pb.DeleteJobRequest{JobId: "j-nosuchjob"})
			return err
		}, codes.NotFound, ""},
	}
	for _, tt := range tests {
		wantCode(t, tt.name, tt.call(), tt.code, tt.field)
	}
	if got := f.job(running.Id).State; got != pb.JobState_JOB_STATE_RUNNING {
		t.Errorf("job after refused actions = %v, want RUNNING still", got)
	}
}

func TestRetryTaskReopensTheFailedJob(t *testing.T) {
	f := newFarm(t)
	job, worker, failed := f.failedJob()
	resp, err := f.jobs.RetryTask(f.ctx, &pb.RetryTaskRequest{TaskId: failed.Lease.TaskId})
	if err != nil || resp.Task.GetState() != pb.TaskState_TASK_STATE_QUEUED || resp.Job.GetState() != pb.JobState_JOB_STATE_QUEUED ||
		resp.Job.GetError() != "" {
		t.Fatalf("RetryTask = %v, %v; want the task and its job queued, the error cleared", resp, err)
	}
	l := f.lease(worker)
	if l.Lease.TaskId != failed.Lease.TaskId || l.Lease.Epoch <= failed.Lease.Epoch {
		t.Fatalf("lease after the retry = %v, want %s under a new epoch", l.Lease, failed.Lease.TaskId)
	}
	if got := f.job(job.Id).State; got != pb.JobState_JOB_STATE_RUNNING {
		t.Errorf("job after its retried task was leased = %v, want RUNNING", got)
	}
	_, err = f.jobs.RetryTask(f.ctx, &pb.RetryTaskRequest{TaskId: failed.Lease.TaskId})
	wantCode(t, "a second retry of the leased task", err, codes.FailedPrecondition, "")
}

func TestRequeueJobReopensItForTheWatch(t *testing.T) {
	f := newFarm(t)
	job, worker, failed := f.failedJob()
	resp, err := f.jobs.RequeueJob(f.ctx, &pb.RequeueJobRequest{JobId: job.Id})
	if err != nil || resp.Job.GetState() != pb.JobState_JOB_STATE_QUEUED || resp.Job.GetFailureKind() != pb.FailureKind_FAILURE_KIND_UNSPECIFIED {
		t.Fatalf("RequeueJob = %v, %v; want the job queued, its failure cleared", resp, err)
	}
	// A watch begun now follows the job again, to its next change.
	stream, err := f.jobs.WatchJob(f.ctx, &pb.WatchJobRequest{JobId: job.Id})
	if err != nil {
		t.Fatal(err)
	}
	if ev, err := stream.Recv(); err != nil || ev.Job.State != pb.JobState_JOB_STATE_QUEUED {
		t.Fatalf("snapshot after the requeue = %v, %v", ev, err)
	}
	if l := f.lease(worker); l.Lease.TaskId != failed.Lease.TaskId {
		t.Errorf("lease after the requeue = %v, want the failed task %s", l.Lease, failed.Lease.TaskId)
	}
	if ev, err := stream.Recv(); err != nil || ev.GetTask().GetState() != pb.TaskState_TASK_STATE_LEASED {
		t.Errorf("event after the lease = %v, %v; want the task leased", ev, err)
	}
	_, err = f.jobs.RequeueJob(f.ctx, &pb.RequeueJobRequest{JobId: job.Id})
	wantCode(t, "requeue of the running job", err, codes.FailedPrecondition, "")
}

func TestDeleteJobEndsTheWatchAndTheJobIsGone(t *testing.T) {
	f := newFarm(t)
	job, w, l := f.leased(scenetest.Unlit(64, 64))
	other := f.submit(scenetest.Unlit(32, 32))
	stream, err := f.jobs.WatchJob(f.ctx, &pb.WatchJobRequest{JobId: job.Id})
	if err != nil {
		t.Fatal(err)
	}
	if _, err := stream.Recv(); err != nil {
		t.Fatal(err)
	}
	resp, err := f.jobs.DeleteJob(f.ctx, &pb.DeleteJobRequest{JobId: job.Id})
	if err != nil || resp.Job.GetState() != pb.JobState_JOB_STATE_CANCELLED {
		t.Fatalf("DeleteJob = %v, %v; want the job as it was deleted, cancelled", resp, err)
	}
	ev, err := stream.Recv()
	if err != nil || ev.Kind != pb.JobEventKind_JOB_EVENT_KIND_STATE_CHANGED || ev.Job.State != pb.JobState_JOB_STATE_CANCELLED {
		t.Fatalf("event after the delete = %v, %v; want the job CANCELLED", ev, err)
	}
	if _, err := stream.Recv(); !errors.Is(err, io.EOF) {
		t.Errorf("watch after the delete: %v, want its end", err)
	}
	_, err = f.jobs.GetJob(f.ctx, &pb.GetJobRequest{JobId: job.Id})
	wantCode(t, "GetJob of the deleted job", err, codes.NotFound, "")
	list, err := f.jobs.ListJobs(f.ctx, &pb.ListJobsRequest{})
	if err != nil || len(list.Jobs) != 1 || list.Jobs[0].Id != other.Id {
		t.Errorf("ListJobs after the delete = %v, %v; want only %s", list, err, other.Id)
	}
	hb, err := f.workers.Heartbeat(f.ctx, &pb.HeartbeatRequest{WorkerId: w, Leases: []*pb.HeldLease{{TaskId: l.Lease.TaskId, Epoch: l.Lease.Epoch}}})
	if err != nil || len(hb.Revoked) != 1 {
		t.Errorf("heartbeat after the delete = %v, %v; want the lease revoked", hb, err)
	}
	_, err = f.jobs.DeleteJob(f.ctx, &pb.DeleteJobRequest{JobId: job.Id})
	wantCode(t, "a second delete", err, codes.NotFound, "")
}
