package storetest

import (
	"fmt"
	"slices"
	"strings"
	"testing"
	"time"

	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// Actions on ended jobs (the store package comment, Reopening): ReopenJob (RequeueJob and
// RetryTask) takes a failed or cancelled job back to where it stopped; DeleteJob removes
// a job at once.

// endings are the ways the suite ends a job of 3 tiles and a composite after tile 0
// succeeded, tile 1 is left leased (or failed) and tile 2 is queued (or in backoff).
// failed names the task left FAILED, if any; stale is a lease the end cancelled.
var endings = []struct {
	name  string
	state pb.JobState
	end   func(f *fixture, job string) (failed string, stale *store.Leased)
}{
	{"PermanentFailure", pb.JobState_JOB_STATE_FAILED, func(f *fixture, job string) (string, *store.Leased) {
		l, other := f.lease("w1"), f.lease("w2")
		f.failKind("w1", l, pb.FailureKind_FAILURE_KIND_BAD_INPUT, "bad mesh")
		return l.Lease.TaskId, other
	}},
	{"FailedAtTheAttemptLimit", pb.JobState_JOB_STATE_FAILED, func(f *fixture, job string) (string, *store.Leased) {
		var l *store.Leased
		for i := 1; i <= maxAttempts; i++ { // by three workers, none blocked
			l = f.lease(fmt.Sprint("w", i))
			f.fail(fmt.Sprint("w", i), l, "flaky")
			f.clock.Advance(f.opts.MaxRetryBackoff)
		}
		return l.Lease.TaskId, nil
	}},
	{"CancelledWithALeaseHeld", pb.JobState_JOB_STATE_CANCELLED, func(f *fixture, job string) (string, *store.Leased) {
		l := f.lease("w1")
		f.cancel(job)
		return "", l
	}},
	{"CancelledWithTasksInBackoff", pb.JobState_JOB_STATE_CANCELLED, func(f *fixture, job string) (string, *store.Leased) {
		f.fail("w1", f.lease("w1"), "flaky")
		f.fail("w2", f.lease("w2"), "flaky")
		f.cancel(job)
		return "", nil
	}},
}

func (f *fixture) cancel(job string) {
	f.t.Helper()
	if _, err := f.s.CancelJob(f.ctx, job); err != nil {
		f.t.Fatalf("CancelJob: %v", err)
	}
}

// endedJob makes a job of 3 tiles and a composite, completes tile 0 and ends it so.
func (f *fixture) endedJob(end func(*fixture, string) (string, *store.Leased)) (*pb.Job, string, *store.Leased) {
	f.t.Helper()
	j := f.create("a", 3)
	f.complete("w0", f.lease("w0"), artifact("tile.exr", "t0"))
	failed, stale := end(f, j.Id)
	return j, failed, stale
}

// finish leases and completes what is left of a job, by workers that no failure blocked,
// and checks that it succeeds leasing each task once.
func (f *fixture) finish(job string) {
	f.t.Helper()
	var leased []string
	for i := 0; ; i++ {
		l, err := f.s.LeaseTask(f.ctx, "w9", store.WorkerPhases)
		if err != nil || l == nil {
			f.t.Fatalf("lease %d of the reopened job = %v, %v; job = %v", i, l, err, f.job(job))
		}
		if slices.Contains(leased, l.Lease.TaskId) {
			f.t.Fatalf("task %s leased twice after reopening (leased %v)", l.Lease.TaskId, leased)
		}
		leased = append(leased, l.Lease.TaskId)
		if c := f.complete("w9", l, artifact("out", l.Lease.TaskId)); c.JobStateChanged {
			break
		}
	}
	if got := f.job(job); got.State != pb.JobState_JOB_STATE_SUCCEEDED || len(got.Outputs) == 0 {
		f.t.Fatalf("reopened job after its last task = %v, want SUCCEEDED with outputs", got)
	}
	f.noLease("w9")
}

func testRequeueReopensWhereTheJobStopped(f *fixture) {
	for _, e := range endings {
		f.t.Run(e.name, func(t *testing.T) {
			f := f.fresh(t)
			j, _, stale := f.endedJob(e.end)
			if got := f.job(j.Id).State; got != e.state {
				t.Fatalf("job ended %v, want %v", got, e.state)
			}
			c, err := f.s.ReopenJob(f.ctx, j.Id, "")
			if err != nil || !c.JobStateChanged || !c.Queued || c.Task != nil {
				t.Fatalf("ReopenJob = %+v, %v; want the job's state changed and tasks queued", c, err)
			}
			job := f.job(j.Id)
			if job.State != pb.JobState_JOB_STATE_QUEUED || job.Error != "" || job.FailureKind != pb.FailureKind_FAILURE_KIND_UNSPECIFIED ||
				job.EndTime != nil {
				t.Fatalf("reopened job = %v, want QUEUED with no error, failure kind or end time", job)
			}
			if got := taskStates(f.tasks(j.Id)); got != "SQQW" {
				t.Errorf("task states = %s, want SQQW (tile 0 stands, the stage queued, the composite waiting)", got)
			}
			for _, task := range f.tasks(j.Id)[1:] {
				if task.RetryTime != nil || task.WorkerId != "" {
					t.Errorf("task %s = %v, want no retry time and no worker", task.Id, task)
				}
			}
			if stale != nil {
				_, err := f.s.CompleteTask(f.ctx, ref(stale.Task.WorkerId, stale), nil)
				wantKind(t, "a report under a lease the end cancelled", err, errs.FailedPrecondition)
			}
			// The failure counts start again: a task may fail maxAttempts-1 more times.
			for i := 1; i < maxAttempts; i++ {
				l := f.lease(fmt.Sprint("x", i))
				if c := f.fail(fmt.Sprint("x", i), l, "again"); c.JobStateChanged {
					t.Fatalf("failure %d after reopening ended the job: %v", i, c.Job)
				}
				f.clock.Advance(f.opts.MaxRetryBackoff)
			}
			if got := f.job(j.Id).State; got != pb.JobState_JOB_STATE_RUNNING {
				t.Fatalf("job after its first lease = %v, want RUNNING", got)
			}
			f.finish(j.Id)
		})
	}
}

func testRetryTaskQueuesItAndReopensTheJob(f *fixture) {
	for _, e := range endings[:2] {
		f.t.Run(e.name, func(t *testing.T) {
			f := f.fresh(t)
			j, failed, _ := f.endedJob(e.end)
			c, err := f.s.ReopenJob(f.ctx, j.Id, failed)
			if err != nil || !c.JobStateChanged || c.Task.GetId() != failed || c.Task.State != pb.TaskState_TASK_STATE_QUEUED ||
				c.Job.State != pb.JobState_JOB_STATE_QUEUED {
				t.Fatalf("ReopenJob(%s, %s) = %+v, %v; want the task and its job queued", j.Id, failed, c, err)
			}
			if got := taskStates(f.tasks(j.Id)); got != "SQQW" {
				t.Errorf("task states = %s, want SQQW", got)
			}
			f.finish(j.Id)
		})
	}
}

func testReopenRefusals(f *fixture) {
	// Made in this order so that each lease goes to the job meant.
	failed, failedTask, _ := f.endedJob(endings[0].end)
	succeeded := f.create("succeeded", 1)
	f.complete("w1", f.lease("w1"), artifact("tile.exr", "t"))
	f.complete("w1", f.lease("w1"), artifact("image.exr", "i"))
	running := f.create("running", 2)
	f.lease("w5")
	queued := f.create("queued", 2)
	t0, t3, q0 := store.TaskID(failed.Id, 0), store.TaskID(failed.Id, 3), store.TaskID(queued.Id, 0)
	tests := []struct {
		name, job, task string
		want            errs.Kind
		says            string // the message, as both stores word it (CheckReopen, CheckRetry)
	}{
		{"SucceededJob", succeeded.Id, "", errs.FailedPrecondition, "job " + succeeded.Id + " succeeded: only a failed or cancelled job can be requeued"},
		{"QueuedJob", queued.Id, "", errs.FailedPrecondition, "job " + queued.Id + " has not ended (JOB_STATE_QUEUED): only a failed or cancelled job can be requeued"},
		{"RunningJob", running.Id, "", errs.FailedPrecondition, "has not ended (JOB_STATE_RUNNING)"},
		{"UnknownJob", "j-nosuchjob", "", errs.NotFound, "j-nosuchjob"},
		{"SucceededTaskOfAFailedJob", failed.Id, t0, errs.FailedPrecondition, "task " + t0 + " is TASK_STATE_SUCCEEDED, not failed: only a failed task can be retried"},
		{"CancelledTaskOfAFailedJob", failed.Id, t3, errs.FailedPrecondition, "task " + t3 + " is TASK_STATE_CANCELLED, not failed"},
		{"QueuedTaskOfAQueuedJob", queued.Id, q0, errs.FailedPrecondition, "task " + q0 + " is TASK_STATE_QUEUED, not failed"},
		{"UnknownTask", failed.Id, store.TaskID(failed.Id, 99), errs.NotFound, store.TaskID(failed.Id, 99)},
		{"TaskOfAnotherJob", running.Id, failedTask, errs.NotFound, failedTask},
	}
	for _, tt := range tests {
		_, err := f.s.ReopenJob(f.ctx, tt.job, tt.task)
		wantKind(f.t, tt.name, err, tt.want)
		if !strings.Contains(err.Error(), tt.says) {
			f.t.Errorf("%s: %v, want it to say %q", tt.name, err, tt.says)
		}
	}
	// Nothing refused changed anything.
	if got := f.job(failed.Id); got.State != pb.JobState_JOB_STATE_FAILED || got.Error == "" {
		f.t.Errorf("failed job after refusals = %v", got)
	}
	if got := f.job(succeeded.Id).State; got != pb.JobState_JOB_STATE_SUCCEEDED {
		f.t.Errorf("succeeded job after a refused reopen = %v", got)
	}
}

func testDeleteJobIsGoneAtOnce(f *fixture) {
	tests := []struct {
		name      string
		make      func(f *fixture) (*pb.Job, *store.Leased)
		cancelled bool
	}{
		{"Running", func(f *fixture) (*pb.Job, *store.Leased) {
			j := f.create("running", 3)
			return j, f.lease("w1")
		}, true},
		{"Queued", func(f *fixture) (*pb.Job, *store.Leased) { return f.create("queued", 2), nil }, true},
		{"Succeeded", func(f *fixture) (*pb.Job, *store.Leased) {
			j := f.create("succeeded", 1)
			f.complete("w1", f.lease("w1"), artifact("tile.exr", "t"))
			f.complete("w1", f.lease("w1"), artifact("image.exr", "i"))
			return j, nil
		}, false},
		{"Failed", func(f *fixture) (*pb.Job, *store.Leased) {
			j, _, stale := f.endedJob(endings[0].end)
			return j, stale
		}, false},
	}
	for _, tt := range tests {
		f.t.Run(tt.name, func(t *testing.T) {
			f := f.fresh(t)
			kept := f.create("kept", 1)
			f.cancel(kept.Id) // ended, but not before the purge's cutoff
			j, l := tt.make(f)
			c, err := f.s.DeleteJob(f.ctx, j.Id)
			if err != nil || c.Job.GetId() != j.Id || c.JobStateChanged != tt.cancelled ||
				(tt.cancelled && c.Job.State != pb.JobState_JOB_STATE_CANCELLED) {
				t.Fatalf("DeleteJob = %+v, %v; want the job, cancelled: %v", c, err, tt.cancelled)
			}
			_, err = f.s.GetJob(f.ctx, j.Id)
			wantKind(t, "GetJob of a deleted job", err, errs.NotFound)
			_, _, err = f.s.ListTasks(f.ctx, j.Id, 10, "")
			wantKind(t, "ListTasks of a deleted job", err, errs.NotFound)
			_, err = f.s.GetTask(f.ctx, store.TaskID(j.Id, 0))
			wantKind(t, "GetTask of a deleted job", err, errs.NotFound)
			jobs, _, err := f.s.ListJobs(f.ctx, 100, "")
			if err != nil || len(jobs) != 1 || jobs[0].Id != kept.Id {
				t.Fatalf("ListJobs after the delete = %v, %v; want only %s", jobs, err, kept.Id)
			}
			if l != nil {
				_, err := f.s.CompleteTask(f.ctx, ref(l.Task.WorkerId, l), nil)
				if k := errs.KindOf(err); k != errs.FailedPrecondition && k != errs.NotFound {
					t.Errorf("a report for a deleted job: %v, want it refused", err)
				}
			}
			f.noLease("w2")
			_, err = f.s.DeleteJob(f.ctx, j.Id)
			wantKind(t, "a second DeleteJob", err, errs.NotFound)
			_, err = f.s.ReopenJob(f.ctx, j.Id, "")
			wantKind(t, "ReopenJob of a deleted job", err, errs.NotFound)
			// Purge steps with no cutoff delete what is left of it, and nothing else.
			if got := f.purge(time.Time{}, 2); slices.Contains(got, kept.Id) {
				t.Errorf("purge after the delete deleted %v, want not %s", got, kept.Id)
			}
			if got := f.job(kept.Id).State; got != pb.JobState_JOB_STATE_CANCELLED {
				t.Errorf("the other job after the purge = %v", got)
			}
		})
	}
}
