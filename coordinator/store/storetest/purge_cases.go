package storetest

import (
	"time"

	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// Retention: ended jobs are deleted with everything they own once PurgeJobs is told they
// ended long enough ago; jobs that have not ended never are.

// purge calls PurgeJobs until it says it is done and returns the jobs deleted.
func (f *fixture) purge(endedBefore time.Time, budget int) []string {
	f.t.Helper()
	var deleted []string
	for step := 0; ; step++ {
		if step == 1000 {
			f.t.Fatalf("PurgeJobs still has work after %d steps", step)
		}
		p, err := f.s.PurgeJobs(f.ctx, endedBefore, start.Add(-time.Hour), budget)
		if err != nil {
			f.t.Fatalf("PurgeJobs: %v", err)
		}
		deleted = append(deleted, p.Deleted...)
		if !p.More {
			return deleted
		}
	}
}

func (f *fixture) createWithRequest(name, requestID string, tiles int) *pb.Job {
	f.t.Helper()
	nj := TileJob(name, tiles)
	nj.RequestID = requestID
	j, err := f.s.CreateJob(f.ctx, nj)
	if err != nil {
		f.t.Fatalf("CreateJob: %v", err)
	}
	return j
}

func testPurgeDeletesEndedJobs(f *fixture) {
	cancelled := f.createWithRequest("cancelled", "req-a", 2)
	if _, err := f.s.CancelJob(f.ctx, cancelled.Id); err != nil {
		f.t.Fatal(err)
	}
	f.clock.Advance(time.Hour)
	succeeded := f.createWithRequest("succeeded", "req-b", 1)
	f.complete("w1", f.lease("w1"), artifact("tile.exr", "t"))
	f.complete("w1", f.lease("w1"), artifact("image.exr", "i"))
	running := f.createWithRequest("running", "req-c", 3)
	f.lease("w1")

	if got := f.purge(start.Add(time.Minute), 1000); len(got) != 1 || got[0] != cancelled.Id {
		f.t.Fatalf("purge of jobs ended before %v deleted %v, want only %s", start.Add(time.Minute), got, cancelled.Id)
	}
	_, err := f.s.GetJob(f.ctx, cancelled.Id)
	wantKind(f.t, "GetJob of a purged job", err, errs.NotFound)
	_, err = f.s.GetTask(f.ctx, store.TaskID(cancelled.Id, 0))
	wantKind(f.t, "GetTask of a purged job's task", err, errs.NotFound)
	_, _, err = f.s.ListTasks(f.ctx, cancelled.Id, 10, "")
	wantKind(f.t, "ListTasks of a purged job", err, errs.NotFound)
	_, err = f.s.CancelJob(f.ctx, cancelled.Id)
	wantKind(f.t, "CancelJob of a purged job", err, errs.NotFound)
	if again := f.createWithRequest("again", "req-a", 1); again.Id == cancelled.Id {
		f.t.Errorf("the purged job's request id still returns it")
	}

	if got := f.purge(f.clock.Now().Add(time.Hour), 1000); len(got) != 1 || got[0] != succeeded.Id {
		f.t.Fatalf("purge of every ended job deleted %v, want %s (the others have not ended)", got, succeeded.Id)
	}
	jobs, _, err := f.s.ListJobs(f.ctx, 100, "")
	if err != nil || len(jobs) != 2 {
		f.t.Fatalf("ListJobs = %d jobs, %v; want the running job and the new one", len(jobs), err)
	}
	if j := f.job(running.Id); j.State != pb.JobState_JOB_STATE_RUNNING || taskStates(f.tasks(running.Id)) != "LQQW" {
		f.t.Errorf("the running job after purges: %v, tasks %s", j.State, taskStates(f.tasks(running.Id)))
	}
	if again := f.createWithRequest("running-retry", "req-c", 3); again.Id != running.Id {
		f.t.Errorf("a live job's request id returned %s, want %s", again.Id, running.Id)
	}
}

func testPurgeGoesInBoundedSteps(f *fixture) {
	const tiles = 40
	big := f.create("big", tiles)
	if _, err := f.s.CancelJob(f.ctx, big.Id); err != nil {
		f.t.Fatal(err)
	}
	p, err := f.s.PurgeJobs(f.ctx, f.clock.Now().Add(time.Second), start.Add(-time.Hour), 8)
	if err != nil {
		f.t.Fatal(err)
	}
	// Whether the first step finished the job is the store's business; the job is gone
	// for reads from the first step on, and the steps end.
	_, err = f.s.GetJob(f.ctx, big.Id)
	wantKind(f.t, "GetJob after a first purge step", err, errs.NotFound)
	deleted := append(p.Deleted, f.purge(f.clock.Now().Add(time.Second), 8)...)
	if len(deleted) != 1 || deleted[0] != big.Id {
		f.t.Errorf("purge steps deleted %v, want %s once", deleted, big.Id)
	}
}
