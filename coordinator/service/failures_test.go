package service_test

import (
	"strings"
	"testing"
	"time"

	"photonfarm/contract/scene/scenetest"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

func (f *farm) failTask(worker string, l *pb.LeaseTaskResponse, kind pb.FailureKind, msg string) {
	f.t.Helper()
	if _, err := f.workers.FailTask(f.ctx, &pb.FailTaskRequest{WorkerId: worker, TaskId: l.Lease.TaskId, Epoch: l.Lease.Epoch, Error: msg, Kind: kind}); err != nil {
		f.t.Fatalf("FailTask: %v", err)
	}
}

func (f *farm) job(id string) *pb.Job {
	f.t.Helper()
	resp, err := f.jobs.GetJob(f.ctx, &pb.GetJobRequest{JobId: id})
	if err != nil {
		f.t.Fatalf("GetJob: %v", err)
	}
	return resp.Job
}

// heartbeat keeps workers heard from (not LOST).
func (f *farm) heartbeat(workers ...string) {
	f.t.Helper()
	for _, w := range workers {
		if _, err := f.workers.Heartbeat(f.ctx, &pb.HeartbeatRequest{WorkerId: w}); err != nil {
			f.t.Fatalf("Heartbeat(%s): %v", w, err)
		}
	}
}

func TestBadInputFailsTheJobAtTheFirstReportAndBlamesNoWorker(t *testing.T) {
	f := newFarm(t)
	job := f.submit(scenetest.Unlit(64, 32))
	w := f.register()
	const reason = "shapes[2].mesh: meshes/broken.obj: line 5: face refers to vertex 7 but the file has 3 vertices"
	l := f.lease(w)
	f.failTask(w, l, pb.FailureKind_FAILURE_KIND_BAD_INPUT, reason)
	got := f.job(job.Id)
	if got.State != pb.JobState_JOB_STATE_FAILED || got.FailureKind != pb.FailureKind_FAILURE_KIND_BAD_INPUT {
		t.Fatalf("job = %v, want FAILED as bad input after one report", got)
	}
	if want := store.PermanentFailure(l.Lease.TaskId, reason); got.Error != want {
		t.Errorf("job error %q, want %q (the task and the reason)", got.Error, want)
	}
	if len(got.BlockedWorkers) != 0 {
		t.Errorf("blocked %v; a permanent failure blames no worker", got.BlockedWorkers)
	}
	if resp, err := f.workers.LeaseTask(f.ctx, &pb.LeaseTaskRequest{WorkerId: w}); err != nil || resp.Lease != nil {
		t.Errorf("lease after the job failed = %v, %v; want nothing", resp, err)
	}
}

func TestJobFailsWhenEveryLiveWorkerIsBlocked(t *testing.T) {
	f := newFarm(t)
	// Six tiles: each worker's three failures land on three different tiles, so no task
	// reaches its attempt limit.
	job := f.submit(scenetest.Unlit(192, 32))
	lost := f.register()
	f.clock.Advance(leaseDuration + time.Second) // lost is not heard from again
	w1, w2 := f.register(), f.register()
	block := func(w, reason string) {
		for range 3 {
			f.failTask(w, f.lease(w), pb.FailureKind_FAILURE_KIND_TRANSIENT, reason)
		}
	}
	block(w1, "out of memory")
	if got := f.job(job.Id); got.State != pb.JobState_JOB_STATE_RUNNING || len(got.BlockedWorkers) != 1 {
		t.Fatalf("after w1 was blocked: job = %v, want it running with w1 blocked", got)
	}
	f.clock.Advance(time.Second)
	f.heartbeat(w1, w2)
	block(w2, "out of disk")
	got := f.job(job.Id)
	want := "every worker (2) is blocked from this job; last: 3 failed tasks: out of disk"
	if got.State != pb.JobState_JOB_STATE_FAILED || got.Error != want || got.FailureKind != pb.FailureKind_FAILURE_KIND_TRANSIENT {
		t.Errorf("job = %v (%q), want FAILED with %q: the lost worker %s does not count", got.State, got.Error, want, lost)
	}
}

func TestBlockedJobWaitsWhileAnotherLiveWorkerMayRunIt(t *testing.T) {
	f := newFarm(t)
	job := f.submit(scenetest.Unlit(192, 32))
	w1, idle := f.register(), f.register()
	for range 3 {
		f.failTask(w1, f.lease(w1), pb.FailureKind_FAILURE_KIND_TRANSIENT, "flaky GPU")
	}
	got := f.job(job.Id)
	if got.State != pb.JobState_JOB_STATE_RUNNING || len(got.BlockedWorkers) != 1 {
		t.Fatalf("job = %v, want it running: %s may still lease it", got, idle)
	}
	if !strings.Contains(got.BlockedWorkers[0].Reason, "flaky GPU") {
		t.Errorf("block reason %q", got.BlockedWorkers[0].Reason)
	}
}

// A job every live worker is blocked from fails even when the last worker that could run
// it is lost after the last block (the check at the block saw it alive).
func TestJobFailsWhenTheLastUnblockedWorkerIsLostAfterTheBlock(t *testing.T) {
	f := newFarm(t)
	job := f.submit(scenetest.Unlit(192, 32))
	w1, other := f.register(), f.register()
	for range 3 {
		f.failTask(w1, f.lease(w1), pb.FailureKind_FAILURE_KIND_TRANSIENT, "flaky GPU")
	}
	if err := f.svc.FailBlockedJobs(f.ctx); err != nil {
		t.Fatal(err)
	}
	if got := f.job(job.Id); got.State != pb.JobState_JOB_STATE_RUNNING {
		t.Fatalf("job = %v while %s may still run it, want it running", got.State, other)
	}
	f.clock.Advance(leaseDuration + time.Second) // other is lost; w1 is still heard from
	f.heartbeat(w1)
	if err := f.svc.FailBlockedJobs(f.ctx); err != nil {
		t.Fatal(err)
	}
	got := f.job(job.Id)
	want := "every worker (1) is blocked from this job; last: 3 failed tasks: flaky GPU"
	if got.State != pb.JobState_JOB_STATE_FAILED || got.Error != want {
		t.Errorf("job = %v (%q), want FAILED with %q once %s was lost", got.State, got.Error, want, other)
	}
}
