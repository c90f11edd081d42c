package storetest

import (
	"fmt"
	"strings"
	"time"

	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// Scheduling and retries: priorities, fair sharing, backoff, expiry and failure limits,
// the blocklist and stuck leases (the store package comment).

func (f *fixture) createPriority(name string, tiles int, priority int32) *pb.Job {
	f.t.Helper()
	nj := TileJob(name, tiles)
	nj.Priority = priority
	j, err := f.s.CreateJob(f.ctx, nj)
	if err != nil {
		f.t.Fatalf("CreateJob(%s, priority %d): %v", name, priority, err)
	}
	return j
}

// leases leases n tasks with worker and returns their ids.
func (f *fixture) leases(worker string, n int) []string {
	f.t.Helper()
	var ids []string
	for i := 0; i < n; i++ {
		ids = append(ids, f.lease(worker).Lease.TaskId)
	}
	return ids
}

func (f *fixture) fail(worker string, l *store.Leased, msg string) store.Change {
	f.t.Helper()
	c, err := f.s.FailTask(f.ctx, ref(worker, l), store.Transient(msg))
	if err != nil {
		f.t.Fatalf("FailTask(%s): %v", l.Lease.TaskId, err)
	}
	return c
}

func ids(jobID string, indices ...uint32) []string {
	var out []string
	for _, i := range indices {
		out = append(out, store.TaskID(jobID, i))
	}
	return out
}

func (f *fixture) wantLeases(what, worker string, want []string) {
	f.t.Helper()
	if got := f.leases(worker, len(want)); fmt.Sprint(got) != fmt.Sprint(want) {
		f.t.Errorf("%s: leased %v, want %v", what, got, want)
	}
}

func testPriorityOrder(f *fixture) {
	low := f.createPriority("low", 2, -5)
	normal := f.createPriority("normal", 2, 0)
	high := f.createPriority("high", 2, store.MaxPriority)
	if got := f.job(high.Id).Priority; got != store.MaxPriority {
		f.t.Errorf("priority = %d, want %d", got, store.MaxPriority)
	}
	want := append(append(ids(high.Id, 0, 1), ids(normal.Id, 0, 1)...), ids(low.Id, 0, 1)...)
	f.wantLeases("by priority", "w1", want)
	for _, p := range []int32{store.MinPriority - 1, store.MaxPriority + 1} {
		nj := TileJob("bad", 1)
		nj.Priority = p
		_, err := f.s.CreateJob(f.ctx, nj)
		wantKind(f.t, fmt.Sprint("CreateJob with priority ", p), err, errs.InvalidArgument)
	}
}

func testFairShare(f *fixture) {
	a := f.create("a", 4)
	b := f.create("b", 4)
	var held []*store.Leased
	for i := 0; i < 4; i++ {
		held = append(held, f.lease("w1")) // a0 b0 a1 b1
	}
	// b finishes its two: holding none, it gets the next two; then both hold two and a,
	// the older, goes next.
	f.complete("w1", held[1])
	f.complete("w1", held[3])
	f.wantLeases("after b's completions", "w1", append(ids(b.Id, 2, 3), store.TaskID(a.Id, 2)))
}

func testSetJobPriority(f *fixture) {
	a := f.create("a", 2)
	b := f.create("b", 2)
	c, err := f.s.SetJobPriority(f.ctx, b.Id, 5)
	if err != nil || c.Job.GetPriority() != 5 || c.Job.GetId() != b.Id {
		f.t.Fatalf("SetJobPriority = %+v, %v", c, err)
	}
	f.wantLeases("b raised", "w1", ids(b.Id, 0, 1))
	if _, err := f.s.SetJobPriority(f.ctx, b.Id, -1); err != nil {
		f.t.Fatal(err)
	}
	if got := f.job(b.Id).Priority; got != -1 {
		f.t.Errorf("priority = %d, want -1", got)
	}
	f.wantLeases("b lowered", "w1", ids(a.Id, 0, 1))

	_, err = f.s.SetJobPriority(f.ctx, "nope", 1)
	wantKind(f.t, "SetJobPriority of an unknown job", err, errs.NotFound)
	_, err = f.s.SetJobPriority(f.ctx, a.Id, store.MaxPriority+1)
	wantKind(f.t, "SetJobPriority out of range", err, errs.InvalidArgument)
	if _, err := f.s.CancelJob(f.ctx, a.Id); err != nil {
		f.t.Fatal(err)
	}
	_, err = f.s.SetJobPriority(f.ctx, a.Id, 1)
	wantKind(f.t, "SetJobPriority of an ended job", err, errs.FailedPrecondition)
}

func testBackoff(f *fixture) {
	j := f.create("a", 2)
	for failures := 1; failures < maxAttempts; failures++ {
		l := f.lease("w1")
		if l.Task.Index != 0 || l.Task.RetryTime != nil {
			f.t.Fatalf("lease after %d failures = %v, want tile 0 without a retry time", failures-1, l.Task)
		}
		c := f.fail("w1", l, "flaky")
		retry := f.clock.Now().Add(f.opts.Backoff(failures))
		if c.Queued || c.Task.State != pb.TaskState_TASK_STATE_QUEUED || !c.Task.GetRetryTime().AsTime().Equal(retry) {
			f.t.Fatalf("failure %d: change = %+v, want the task queued until %v and Queued unset", failures, c, retry)
		}
		if got := f.tasks(j.Id)[0].GetRetryTime().AsTime(); !got.Equal(retry) {
			f.t.Errorf("listed retry time = %v, want %v", got, retry)
		}
		other := f.lease("w2") // the other tile is leased meanwhile
		if other.Task.Index != 1 {
			f.t.Fatalf("leased %v during the backoff, want tile 1", other.Task)
		}
		f.noLease("w2")
		f.clock.Advance(f.opts.Backoff(failures) - time.Millisecond)
		f.noLease("w2")
		f.clock.Advance(time.Millisecond)
		if _, err := f.s.ReleaseTask(f.ctx, ref("w2", other)); err != nil {
			f.t.Fatal(err)
		}
	}
	if d := f.opts.Backoff(2); d != 2*f.opts.RetryBackoff {
		f.t.Errorf("second backoff = %v, want twice %v", d, f.opts.RetryBackoff)
	}
}

func testExpiryLimit(f *fixture) {
	j := f.create("a", 1)
	for n := 1; n <= maxExpiries; n++ {
		l := f.lease("w1") // expiries do not block a worker
		f.clock.Advance(leaseDuration)
		cs, err := f.s.ExpireLeases(f.ctx)
		if err != nil || len(cs) != 1 {
			f.t.Fatalf("expiry %d: ExpireLeases = %v, %v", n, cs, err)
		}
		c := cs[0]
		if c.Task.Error != store.ExpiredMessage || c.Task.Id != l.Lease.TaskId || c.Task.FailureKind != pb.FailureKind_FAILURE_KIND_TRANSIENT {
			f.t.Errorf("expiry %d: task = %v, want error %q", n, c.Task, store.ExpiredMessage)
		}
		if n < maxExpiries {
			if c.JobStateChanged || c.Task.State != pb.TaskState_TASK_STATE_QUEUED || c.Task.RetryTime != nil {
				f.t.Fatalf("expiry %d: change = %+v, want the task queued at once", n, c)
			}
			continue
		}
		want := store.JobFailure(l.Lease.TaskId, maxExpiries, store.ExpiredMessage)
		if !c.JobStateChanged || c.Job.State != pb.JobState_JOB_STATE_FAILED || c.Job.Error != want || c.Task.State != pb.TaskState_TASK_STATE_FAILED ||
			c.Job.FailureKind != pb.FailureKind_FAILURE_KIND_TRANSIENT {
			f.t.Fatalf("last expiry: change = %+v, want the job FAILED with %q", c, want)
		}
	}
	if got := taskStates(f.tasks(j.Id)); got != "FC" {
		f.t.Errorf("states = %s, want FC", got)
	}
	f.noLease("w2")
}

func testBlocklist(f *fixture) {
	a := f.create("a", 5)
	b := f.create("b", 1)
	var last store.Change
	for i := 1; i <= blockAfter; i++ {
		l := f.lease("w1") // a's tiles 0, 1, 2 in turn (fewest held leases; a is older)
		if l.Task.JobId != a.Id {
			f.t.Fatalf("lease %d = %s, want a task of %s", i, l.Lease.TaskId, a.Id)
		}
		if len(f.job(a.Id).BlockedWorkers) != 0 {
			f.t.Fatalf("w1 blocked after %d failures", i-1)
		}
		last = f.fail("w1", l, fmt.Sprint("out of memory ", i))
	}
	want := &pb.BlockedWorker{WorkerId: "w1", Reason: store.BlockReason(blockAfter, fmt.Sprint("out of memory ", blockAfter))}
	for what, j := range map[string]*pb.Job{"change": last.Job, "GetJob": f.job(a.Id)} {
		bw := j.GetBlockedWorkers()
		if len(bw) != 1 || bw[0].WorkerId != want.WorkerId || bw[0].Reason != want.Reason || !bw[0].BlockTime.AsTime().Equal(f.clock.Now()) {
			f.t.Errorf("%s: blocked workers = %v, want %v at %v", what, bw, want, f.clock.Now())
		}
	}
	f.clock.Advance(f.opts.MaxRetryBackoff) // every backoff is over
	if l := f.lease("w1"); l.Task.JobId != b.Id {
		f.t.Errorf("blocked w1 leased %s, want b's tile", l.Lease.TaskId)
	}
	f.noLease("w1")
	if l := f.lease("w2"); l.Task.JobId != a.Id {
		f.t.Errorf("w2 leased %s, want a task of a", l.Lease.TaskId)
	}

	c, err := f.s.UnblockWorker(f.ctx, a.Id, "w9") // not blocked: nothing changes
	if err != nil || c.Queued || len(c.Job.GetBlockedWorkers()) != 1 {
		f.t.Fatalf("UnblockWorker(w9) = %+v, %v", c, err)
	}
	if c, err = f.s.UnblockWorker(f.ctx, a.Id, ""); err != nil || !c.Queued || len(c.Job.GetBlockedWorkers()) != 0 {
		f.t.Fatalf("UnblockWorker(all) = %+v, %v", c, err)
	}
	if l := f.lease("w1"); l.Task.JobId != a.Id {
		f.t.Errorf("unblocked w1 leased %s, want a task of a", l.Lease.TaskId)
	}
	// The count started again: one more failure does not block w1.
	f.fail("w1", f.lease("w1"), "again")
	if bw := f.job(a.Id).BlockedWorkers; len(bw) != 0 {
		f.t.Errorf("blocked after one failure since unblocking: %v", bw)
	}
	_, err = f.s.UnblockWorker(f.ctx, "nope", "w1")
	wantKind(f.t, "UnblockWorker of an unknown job", err, errs.NotFound)
}

func testStuck(f *fixture) {
	const step = leaseDuration / 2
	f.create("a", 2)
	busy, idle := f.lease("w1"), f.lease("w1")
	for i := 1; time.Duration(i)*step <= stuckTimeout; i++ {
		f.clock.Advance(step)
		hb, err := f.s.ExtendLeases(f.ctx, "w1", []*pb.HeldLease{
			{TaskId: busy.Lease.TaskId, Epoch: busy.Lease.Epoch, Progress: uint64(i)},
			{TaskId: idle.Lease.TaskId, Epoch: idle.Lease.Epoch, Progress: 0},
		})
		if err != nil {
			f.t.Fatal(err)
		}
		if len(hb.Extended) == 0 || hb.Extended[0].TaskId != busy.Lease.TaskId {
			f.t.Fatalf("after %v: extended %v, want the lease whose progress grows", time.Duration(i)*step, hb.Extended)
		}
		if time.Duration(i)*step < stuckTimeout {
			if len(hb.Extended) != 2 || len(hb.Revoked) != 0 {
				f.t.Fatalf("after %v: heartbeat = %+v, want both leases extended", time.Duration(i)*step, hb)
			}
			continue
		}
		if len(hb.Revoked) != 1 || hb.Revoked[0].TaskId != idle.Lease.TaskId || len(hb.Changes) != 1 {
			f.t.Fatalf("after %v: heartbeat = %+v, want the idle lease revoked", stuckTimeout, hb)
		}
		c := hb.Changes[0]
		if c.Task.State != pb.TaskState_TASK_STATE_QUEUED || c.Task.Error != f.opts.StuckMessage() || c.Task.RetryTime == nil ||
			!strings.Contains(c.Task.Error, "no progress for 1m0s") {
			f.t.Errorf("stuck change = %+v, want a failed attempt %q with a backoff", c, f.opts.StuckMessage())
		}
	}
	_, err := f.s.CompleteTask(f.ctx, ref("w1", idle), nil)
	wantKind(f.t, "complete under the stuck lease", err, errs.FailedPrecondition)

	// The builder's leases report no progress and are never stuck.
	f.createPhotonJob("p", 1, 1)
	f.complete("w1", f.leaseOf("w1", []pb.Phase{pb.Phase_PHASE_EMIT}))
	build := f.leaseOf("builder", store.BuilderPhases)
	for elapsed := time.Duration(0); elapsed <= 2*stuckTimeout; elapsed += step {
		f.clock.Advance(step)
		hb, err := f.s.ExtendLeases(f.ctx, "builder", []*pb.HeldLease{{TaskId: build.Lease.TaskId, Epoch: build.Lease.Epoch}})
		if err != nil || len(hb.Extended) != 1 {
			f.t.Fatalf("builder heartbeat after %v = %+v, %v; want the lease extended", elapsed+step, hb, err)
		}
	}
}
