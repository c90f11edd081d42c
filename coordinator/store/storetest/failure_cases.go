package storetest

import (
	"fmt"
	"time"

	"google.golang.org/protobuf/proto"

	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// Failure kinds (the store package comment): permanent ones end the job at once and
// blame no worker, the others retry; and a job every known worker is blocked from fails.

func (f *fixture) failKind(worker string, l *store.Leased, kind pb.FailureKind, msg string) store.Change {
	f.t.Helper()
	c, err := f.s.FailTask(f.ctx, ref(worker, l), store.Failure{Message: msg, Kind: kind})
	if err != nil {
		f.t.Fatalf("FailTask(%s, %v): %v", l.Lease.TaskId, kind, err)
	}
	return c
}

func testPermanentFailure(f *fixture) {
	const msg = "shapes[8].mesh: meshes/broken.obj: line 5: face refers to vertex 7 but the file has 3 vertices"
	for _, kind := range []pb.FailureKind{pb.FailureKind_FAILURE_KIND_BAD_INPUT, pb.FailureKind_FAILURE_KIND_UNSUPPORTED, pb.FailureKind_FAILURE_KIND_LOST_INPUT} {
		j := f.create(kind.String(), 3)
		// Two transient failures first: with the permanent one they would reach the
		// blocklist threshold if it counted.
		for i := 1; i < blockAfter; i++ {
			f.fail("w1", f.lease("w1"), "flaky")
			f.clock.Advance(f.opts.MaxRetryBackoff)
		}
		l, other := f.lease("w1"), f.lease("w2")
		c := f.failKind("w1", l, kind, msg)
		want := store.PermanentFailure(l.Lease.TaskId, msg)
		if !c.JobStateChanged || c.Job.State != pb.JobState_JOB_STATE_FAILED || c.Job.Error != want || c.Job.FailureKind != kind {
			f.t.Fatalf("%v: change = %+v, want the job FAILED at once with %q and kind %v", kind, c.Job, want, kind)
		}
		if c.Task.State != pb.TaskState_TASK_STATE_FAILED || c.Task.FailureKind != kind || c.Task.Error != msg {
			f.t.Errorf("%v: task = %v, want FAILED with the report's error and kind", kind, c.Task)
		}
		job := f.job(j.Id)
		if len(job.BlockedWorkers) != 0 || job.FailureKind != kind || job.Error != want || job.EndTime == nil {
			f.t.Errorf("%v: job = %v, want it failed with no worker blocked", kind, job)
		}
		_, err := f.s.CompleteTask(f.ctx, ref("w2", other), nil)
		wantKind(f.t, "complete another task of the failed job", err, errs.FailedPrecondition)
		f.noLease("w1")
	}
}

func testTransientKinds(f *fixture) {
	j := f.create("a", 1)
	kinds := []pb.FailureKind{pb.FailureKind_FAILURE_KIND_UNSPECIFIED, pb.FailureKind_FAILURE_KIND_TRANSIENT, pb.FailureKind_FAILURE_KIND_RESOURCE_EXHAUSTED}
	for i, kind := range kinds {
		c := f.failKind(fmt.Sprint("w", i), f.lease(fmt.Sprint("w", i)), kind, fmt.Sprint("failure ", i))
		if c.Task.FailureKind != kind || c.Task.Error != fmt.Sprint("failure ", i) {
			f.t.Errorf("failure %d: task = %v, want its kind %v recorded", i, c.Task, kind)
		}
		if i < maxAttempts-1 {
			if c.JobStateChanged || c.Task.State != pb.TaskState_TASK_STATE_QUEUED || c.Task.RetryTime == nil {
				f.t.Fatalf("failure %d (%v): change = %+v, want a retry after a backoff", i, kind, c)
			}
			f.clock.Advance(f.opts.MaxRetryBackoff)
			continue
		}
		want := store.JobFailure(c.Task.Id, maxAttempts, fmt.Sprint("failure ", i))
		if c.Job.State != pb.JobState_JOB_STATE_FAILED || c.Job.Error != want || c.Job.FailureKind != kind {
			f.t.Errorf("last failure: job = %v, want FAILED with %q and the last kind %v", c.Job, want, kind)
		}
	}
	if got := f.job(j.Id).FailureKind; got != pb.FailureKind_FAILURE_KIND_RESOURCE_EXHAUSTED {
		f.t.Errorf("stored job failure kind = %v", got)
	}
}

func testResourceExhaustionBlamesNoWorker(f *fixture) {
	a := f.create("a", 2*blockAfter)
	for i := 0; i < 2*blockAfter; i++ { // each a different tile: no task reaches its attempt limit
		c := f.failKind("w1", f.lease("w1"), pb.FailureKind_FAILURE_KIND_RESOURCE_EXHAUSTED, "cache full")
		if c.JobStateChanged || len(c.Job.GetBlockedWorkers()) != 0 {
			f.t.Fatalf("resource exhaustion %d: job = %v, want it running with no worker blocked", i+1, c.Job)
		}
	}
	if bw := f.job(a.Id).BlockedWorkers; len(bw) != 0 {
		f.t.Fatalf("blocked workers = %v after %d resource exhaustions, want none", bw, 2*blockAfter)
	}
	// A transient failure after them counts from one: w1 is not blocked yet.
	f.clock.Advance(f.opts.MaxRetryBackoff)
	f.failKind("w1", f.lease("w1"), pb.FailureKind_FAILURE_KIND_TRANSIENT, "flaky")
	if bw := f.job(a.Id).BlockedWorkers; len(bw) != 0 {
		f.t.Errorf("blocked workers = %v after one transient failure, want none", bw)
	}
}

func testFailBlockedJob(f *fixture) {
	a := f.create("a", 6)
	blockWorker := func(worker, msg string) {
		f.t.Helper()
		for i := 0; i < blockAfter; i++ {
			f.failKind(worker, f.lease(worker), pb.FailureKind_FAILURE_KIND_TRANSIENT, msg)
		}
	}
	nothing := func(what string, workers ...string) {
		f.t.Helper()
		c, err := f.s.FailBlockedJob(f.ctx, a.Id, workers)
		if err != nil || c.Job != nil {
			f.t.Fatalf("%s: FailBlockedJob(%v) = %+v, %v; want no change", what, workers, c, err)
		}
	}
	blockWorker("w1", "out of memory")
	nothing("one of two blocked", "w1", "w2")
	nothing("no worker known")
	f.clock.Advance(time.Second)
	blockWorker("w2", "out of disk")
	nothing("a third worker not blocked", "w1", "w2", "w3")

	c, err := f.s.FailBlockedJob(f.ctx, a.Id, []string{"w2", "w1"})
	want := store.BlockedJobFailure(2, store.BlockReason(blockAfter, "out of disk"))
	if err != nil || !c.JobStateChanged || c.Job.State != pb.JobState_JOB_STATE_FAILED || c.Job.Error != want ||
		c.Job.FailureKind != pb.FailureKind_FAILURE_KIND_TRANSIENT {
		f.t.Fatalf("every worker blocked: FailBlockedJob = %+v, %v; want the job FAILED with %q", c.Job, err, want)
	}
	if got := taskStates(f.tasks(a.Id)); got != "CCCCCCC" { // six tiles and the composite
		f.t.Errorf("states = %s, want every task cancelled", got)
	}
	nothing("the job has ended", "w1", "w2")
	_, err = f.s.FailBlockedJob(f.ctx, "nope", []string{"w1"})
	wantKind(f.t, "FailBlockedJob of an unknown job", err, errs.NotFound)
}

// A failed attempt's log is the task's Task.log until a later failure sends another (one
// without a log keeps it); a success's log is among its outputs, the failed attempt's
// still on the task; a permanent failure's log is on the failed task.
func testTaskLogs(f *fixture) {
	logOf := func(attempt string) *pb.Artifact { return artifact("task.log", "log of "+attempt) }
	failWithLog := func(worker string, kind pb.FailureKind, log *pb.Artifact) store.Change {
		f.t.Helper()
		c, err := f.s.FailTask(f.ctx, ref(worker, f.lease(worker)), store.Failure{Message: "flaky", Kind: kind, Log: log})
		if err != nil {
			f.t.Fatalf("FailTask: %v", err)
		}
		f.clock.Advance(f.opts.MaxRetryBackoff)
		return c
	}
	a := f.create("a", 1)
	for i, step := range []struct {
		worker string
		log    *pb.Artifact
		want   *pb.Artifact
	}{
		{"w1", logOf("1"), logOf("1")},
		{"w2", nil, logOf("1")}, // no log sent: the last one stays
	} {
		c := failWithLog(step.worker, pb.FailureKind_FAILURE_KIND_TRANSIENT, step.log)
		if !proto.Equal(c.Task.GetLog(), step.want) {
			f.t.Errorf("failure %d: change's task log = %v, want %v", i+1, c.Task.GetLog(), step.want)
		}
		if got := f.tasks(a.Id)[0].GetLog(); !proto.Equal(got, step.want) {
			f.t.Errorf("failure %d: stored task log = %v, want %v", i+1, got, step.want)
		}
	}
	done := logOf("3")
	f.complete("w3", f.lease("w3"), artifact("tile.exr", "t0"), done)
	t := f.tasks(a.Id)[0]
	if t.State != pb.TaskState_TASK_STATE_SUCCEEDED || len(t.Outputs) != 2 || !proto.Equal(t.Outputs[1], done) {
		f.t.Errorf("completed task = %v, want SUCCEEDED with its log among its outputs", t)
	}
	if !proto.Equal(t.GetLog(), logOf("1")) {
		f.t.Errorf("completed task's log = %v, want the last failed attempt's %v", t.GetLog(), logOf("1"))
	}

	// Job a's composite.
	c := failWithLog("w4", pb.FailureKind_FAILURE_KIND_BAD_INPUT, logOf("composite"))
	if stored := f.tasks(a.Id)[c.Task.GetIndex()]; c.Task.State != pb.TaskState_TASK_STATE_FAILED || !proto.Equal(stored.GetLog(), logOf("composite")) {
		f.t.Errorf("permanently failed task = %v, want FAILED with its log %v", stored, logOf("composite"))
	}
}
