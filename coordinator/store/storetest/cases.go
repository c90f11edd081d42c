package storetest

import (
	"fmt"
	"strings"
	"sync"
	"time"

	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

func testCreateJob(f *fixture) {
	j := f.create("a", 3)
	if j.Id == "" || j.State != pb.JobState_JOB_STATE_QUEUED || j.DisplayName != "a" || j.SceneDigest != digest("a") {
		f.t.Fatalf("CreateJob = %v", j)
	}
	if !j.CreateTime.AsTime().Equal(start) || j.EndTime != nil {
		f.t.Errorf("times: create %v end %v", j.CreateTime.AsTime(), j.EndTime)
	}
	if len(j.Phases) != 2 || j.Phases[0].Phase != pb.Phase_PHASE_RENDER || j.Phases[0].TasksTotal != 3 ||
		j.Phases[1].Phase != pb.Phase_PHASE_COMPOSITE || j.Phases[1].TasksTotal != 1 {
		f.t.Errorf("phases = %v", j.Phases)
	}
	ts := f.tasks(j.Id)
	if got := taskStates(ts); got != "QQQW" {
		f.t.Errorf("task states = %s, want QQQW", got)
	}
	for i, task := range ts {
		if task.Id != store.TaskID(j.Id, uint32(i)) || task.JobId != j.Id || task.Index != uint32(i) {
			f.t.Errorf("task %d = %v", i, task)
		}
	}
	if ts[1].GetRenderTile().GetRect().GetX() != 8 || ts[3].GetComposite() == nil {
		f.t.Errorf("specs not kept: %v", ts)
	}
}

func testCreateJobRequestID(f *fixture) {
	create := func(name, requestID string) *pb.Job {
		f.t.Helper()
		nj := TileJob(name, 2)
		nj.RequestID = requestID
		j, err := f.s.CreateJob(f.ctx, nj)
		if err != nil {
			f.t.Fatalf("CreateJob(%s, %q): %v", name, requestID, err)
		}
		return j
	}
	first := create("a", "req-1")
	f.lease("w1") // the retry must return the job as it stands, not reset it
	again := create("a-retry", "req-1")
	if again.Id != first.Id || again.DisplayName != "a" || again.State != pb.JobState_JOB_STATE_RUNNING {
		f.t.Errorf("retried CreateJob = %v, want job %s as it stands", again, first.Id)
	}
	other := create("b", "req-2")
	anon1, anon2 := create("c", ""), create("c", "")
	if other.Id == first.Id || anon1.Id == anon2.Id {
		f.t.Errorf("distinct submissions share a job: %s %s, %s %s", first.Id, other.Id, anon1.Id, anon2.Id)
	}
	jobs, _, err := f.s.ListJobs(f.ctx, 100, "")
	if err != nil || len(jobs) != 4 {
		f.t.Errorf("ListJobs = %d jobs, %v; want 4 (the retry created nothing)", len(jobs), err)
	}
	if got := taskStates(f.tasks(first.Id)); got != "LQW" {
		f.t.Errorf("states of the first job = %s, want LQW", got)
	}
}

func testGetJobUnknown(f *fixture) {
	_, err := f.s.GetJob(f.ctx, "nope")
	wantKind(f.t, "GetJob", err, errs.NotFound)
	_, _, err = f.s.ListTasks(f.ctx, "nope", 10, "")
	wantKind(f.t, "ListTasks", err, errs.NotFound)
	_, err = f.s.CancelJob(f.ctx, "nope")
	wantKind(f.t, "CancelJob", err, errs.NotFound)
}

func testLeaseNothing(f *fixture) {
	f.noLease("w1")
	j := f.create("a", 1)
	l := f.lease("w1")
	f.noLease("w2") // the composite waits for the tile
	f.complete("w1", l)
	f.lease("w1")
	f.noLease("w2")
	_ = j
}

func testLeaseShares(f *fixture) {
	a := f.create("a", 2)
	b := f.create("b", 2)
	want := []string{store.TaskID(a.Id, 0), store.TaskID(b.Id, 0), store.TaskID(a.Id, 1), store.TaskID(b.Id, 1)}
	var got []*store.Leased
	for i, w := range want {
		l := f.lease("w1")
		if l.Lease.TaskId != w || l.Task.Id != w {
			f.t.Fatalf("lease %d = %s, want %s", i, l.Lease.TaskId, w)
		}
		got = append(got, l)
	}
	// A task that goes back keeps its place in its job: a, now holding fewer leases than
	// b, gives its tile 0 next.
	if _, err := f.s.ReleaseTask(f.ctx, ref("w1", got[0])); err != nil {
		f.t.Fatal(err)
	}
	if l := f.lease("w2"); l.Lease.TaskId != want[0] {
		f.t.Errorf("after release leased %s, want %s", l.Lease.TaskId, want[0])
	}
	l := got[1]
	if l.SceneDigest != digest("b") || l.Task.State != pb.TaskState_TASK_STATE_LEASED || l.Task.WorkerId != "w1" ||
		l.Task.Attempts != 1 || l.Lease.Epoch == 0 || !l.Lease.ExpireTime.AsTime().Equal(start.Add(leaseDuration)) {
		f.t.Errorf("leased = %v", l)
	}
}

func testFirstLeaseStartsJob(f *fixture) {
	j := f.create("a", 2)
	l := f.lease("w1")
	if !l.Change.JobStateChanged || l.Change.Job.State != pb.JobState_JOB_STATE_RUNNING || l.Change.Task.Id != l.Lease.TaskId {
		f.t.Errorf("first lease change = %+v", l.Change)
	}
	if l2 := f.lease("w1"); l2.Change.JobStateChanged {
		f.t.Error("second lease reported a job state change")
	}
	// The caller fills Leased.Task's spec while Change is published to watchers: they
	// must be separate messages.
	l.Task.Error = "filled in by the caller"
	if l.Change.Task.Error != "" {
		f.t.Error("Leased.Task and Leased.Change.Task are one message")
	}
	if got := f.job(j.Id).State; got != pb.JobState_JOB_STATE_RUNNING {
		f.t.Errorf("job state = %v, want RUNNING", got)
	}
}

func testPhaseOpening(f *fixture) {
	j := f.create("a", 2)
	l0, l1 := f.lease("w1"), f.lease("w2")
	if c := f.complete("w2", l1, artifact("tile.exr", "t1")); c.Queued || c.Task.State != pb.TaskState_TASK_STATE_SUCCEEDED {
		f.t.Errorf("first tile change = %+v", c)
	}
	if got := taskStates(f.tasks(j.Id)); got != "LSW" {
		f.t.Errorf("states = %s, want LSW", got)
	}
	if c := f.complete("w1", l0, artifact("tile.exr", "t0")); !c.Queued || c.JobStateChanged {
		f.t.Errorf("last tile change = %+v, want Queued", c)
	}
	if got := taskStates(f.tasks(j.Id)); got != "SSQ" {
		f.t.Errorf("states = %s, want SSQ", got)
	}
	job := f.job(j.Id)
	if job.Phases[0].TasksSucceeded != 2 || job.Phases[1].TasksSucceeded != 0 {
		f.t.Errorf("progress = %v", job.Phases)
	}
	ts := f.tasks(j.Id)
	if len(ts[0].Outputs) != 1 || ts[0].Outputs[0].Digest != digest("t0") {
		f.t.Errorf("outputs of tile 0 = %v", ts[0].Outputs)
	}
}

func testJobSucceeds(f *fixture) {
	j := f.create("a", 1)
	f.complete("w1", f.lease("w1"), artifact("tile.exr", "t0"))
	comp := f.lease("w1")
	if comp.Task.GetComposite() == nil {
		f.t.Fatalf("leased %v, want the composite", comp.Task)
	}
	f.clock.Advance(time.Second)
	c := f.complete("w1", comp, artifact("image.exr", "img"), artifact("preview.png", "png"))
	if !c.JobStateChanged || c.Job.State != pb.JobState_JOB_STATE_SUCCEEDED {
		f.t.Fatalf("change = %+v, want the job SUCCEEDED", c)
	}
	job := f.job(j.Id)
	if job.State != pb.JobState_JOB_STATE_SUCCEEDED || job.EndTime == nil || !job.EndTime.AsTime().Equal(start.Add(time.Second)) {
		f.t.Errorf("job = %v", job)
	}
	if len(job.Outputs) != 2 || job.Outputs[0].Name != "image.exr" || job.Outputs[1].Digest != digest("png") {
		f.t.Errorf("job outputs = %v", job.Outputs)
	}
	f.noLease("w1")
	_, err := f.s.CancelJob(f.ctx, j.Id)
	wantKind(f.t, "CancelJob of a finished job", err, errs.FailedPrecondition)
}

func testIdempotentComplete(f *fixture) {
	f.create("a", 2)
	l := f.lease("w1")
	f.complete("w1", l, artifact("tile.exr", "t0"))
	c := f.complete("w1", l, artifact("tile.exr", "t0"))
	if c.Job != nil || c.Task != nil {
		f.t.Errorf("repeated complete changed something: %+v", c)
	}
	_, err := f.s.CompleteTask(f.ctx, ref("w2", l), nil)
	wantKind(f.t, "complete by another worker", err, errs.FailedPrecondition)
	_, err = f.s.FailTask(f.ctx, ref("w1", l), store.Transient("late failure"))
	wantKind(f.t, "fail after success", err, errs.FailedPrecondition)
}

func testStaleReports(f *fixture) {
	f.create("a", 1)
	l := f.lease("w1")
	stale := ref("w1", l)
	stale.Epoch--
	_, err := f.s.CompleteTask(f.ctx, stale, nil)
	wantKind(f.t, "complete under an older epoch", err, errs.FailedPrecondition)
	stale.Epoch += 2
	_, err = f.s.CompleteTask(f.ctx, stale, nil)
	wantKind(f.t, "complete under a future epoch", err, errs.FailedPrecondition)
	_, err = f.s.FailTask(f.ctx, ref("w2", l), store.Transient("x"))
	wantKind(f.t, "fail by another worker", err, errs.FailedPrecondition)
	_, err = f.s.ReleaseTask(f.ctx, ref("w2", l))
	wantKind(f.t, "release by another worker", err, errs.FailedPrecondition)
	_, err = f.s.CompleteTask(f.ctx, store.LeaseRef{WorkerID: "w1", TaskID: "nope.0", Epoch: 1}, nil)
	wantKind(f.t, "complete of an unknown task", err, errs.NotFound)
	f.complete("w1", l) // the real lease still works
}

func testExpiry(f *fixture) {
	j := f.create("a", 1)
	l1 := f.lease("w1")
	f.clock.Advance(leaseDuration - time.Millisecond)
	if cs, err := f.s.ExpireLeases(f.ctx); err != nil || len(cs) != 0 {
		f.t.Fatalf("ExpireLeases before the deadline = %v, %v", cs, err)
	}
	f.clock.Advance(time.Millisecond)
	cs, err := f.s.ExpireLeases(f.ctx)
	if err != nil || len(cs) != 1 || !cs[0].Queued || cs[0].Task.State != pb.TaskState_TASK_STATE_QUEUED || cs[0].Task.WorkerId != "" {
		f.t.Fatalf("ExpireLeases = %+v, %v; want the task requeued", cs, err)
	}
	l2 := f.lease("w2")
	if l2.Lease.TaskId != l1.Lease.TaskId || l2.Lease.Epoch <= l1.Lease.Epoch || l2.Task.Attempts != 2 {
		f.t.Errorf("re-lease = %v (first %v), want the same task, a larger epoch and 2 attempts", l2.Lease, l1.Lease)
	}
	_, err = f.s.CompleteTask(f.ctx, ref("w1", l1), nil)
	wantKind(f.t, "complete under the expired lease", err, errs.FailedPrecondition)
	f.complete("w2", l2)
	if got := taskStates(f.tasks(j.Id)); got != "SQ" {
		f.t.Errorf("states = %s", got)
	}
}

func testReportAfterDeadline(f *fixture) {
	f.create("a", 1)
	l := f.lease("w1")
	f.clock.Advance(leaseDuration)
	_, err := f.s.CompleteTask(f.ctx, ref("w1", l), nil)
	wantKind(f.t, "complete after the deadline", err, errs.FailedPrecondition)
}

func testExtend(f *fixture) {
	f.create("a", 2)
	l0, l1 := f.lease("w1"), f.lease("w1")
	f.clock.Advance(leaseDuration / 2)
	held := []*pb.HeldLease{
		{TaskId: l0.Lease.TaskId, Epoch: l0.Lease.Epoch},
		{TaskId: l1.Lease.TaskId, Epoch: l1.Lease.Epoch + 7},
		{TaskId: "nope.3", Epoch: 1},
	}
	hb, err := f.s.ExtendLeases(f.ctx, "w1", held)
	if err != nil {
		f.t.Fatal(err)
	}
	ext, rev := hb.Extended, hb.Revoked
	if len(ext) != 1 || ext[0].TaskId != l0.Lease.TaskId || !ext[0].ExpireTime.AsTime().Equal(start.Add(leaseDuration/2+leaseDuration)) {
		f.t.Errorf("extended = %v", ext)
	}
	if len(rev) != 2 || rev[0].TaskId != l1.Lease.TaskId || rev[1].TaskId != "nope.3" {
		f.t.Errorf("revoked = %v", rev)
	}
	if hb, _ = f.s.ExtendLeases(f.ctx, "w2", held[:1]); len(hb.Revoked) != 1 {
		f.t.Errorf("another worker extended w1's lease")
	}
	f.clock.Advance(leaseDuration/2 + time.Millisecond)
	cs, _ := f.s.ExpireLeases(f.ctx)
	if len(cs) != 1 || cs[0].Task.Id != l1.Lease.TaskId {
		f.t.Fatalf("expired %v, want only the unextended lease", cs)
	}
	f.complete("w1", l0)
}

func testFailRetries(f *fixture) {
	j := f.create("a", 2)
	other := f.lease("w9")
	for attempt := 1; attempt <= maxAttempts; attempt++ {
		l := f.lease("w1")
		if l.Task.Index != 1 || l.Task.Attempts != uint32(attempt) {
			f.t.Fatalf("attempt %d leased %v", attempt, l.Task)
		}
		c, err := f.s.FailTask(f.ctx, ref("w1", l), store.Failure{Message: fmt.Sprintf("boom %d", attempt)})
		if err != nil {
			f.t.Fatal(err)
		}
		if attempt < maxAttempts {
			f.clock.Advance(f.opts.Backoff(attempt))
			if c.JobStateChanged || c.Task.State != pb.TaskState_TASK_STATE_QUEUED || c.Task.Error != fmt.Sprintf("boom %d", attempt) {
				f.t.Fatalf("failure %d change = %+v, want a retry", attempt, c)
			}
			continue
		}
		if !c.JobStateChanged || c.Job.State != pb.JobState_JOB_STATE_FAILED || !strings.Contains(c.Job.Error, "boom 3") ||
			c.Task.State != pb.TaskState_TASK_STATE_FAILED {
			f.t.Fatalf("last failure change = %+v, want the job FAILED with the task's error", c)
		}
	}
	job := f.job(j.Id)
	if job.State != pb.JobState_JOB_STATE_FAILED || job.EndTime == nil {
		f.t.Errorf("job = %v", job)
	}
	if got := taskStates(f.tasks(j.Id)); got != "CFC" {
		f.t.Errorf("states = %s, want CFC", got)
	}
	_, err := f.s.CompleteTask(f.ctx, ref("w9", other), nil)
	wantKind(f.t, "complete in a failed job", err, errs.FailedPrecondition)
	f.noLease("w1")
}

func testRelease(f *fixture) {
	j := f.create("a", 1)
	for i := 0; i < 2*maxAttempts; i++ {
		l := f.lease("w1")
		c, err := f.s.ReleaseTask(f.ctx, ref("w1", l))
		if err != nil || !c.Queued || c.Task.State != pb.TaskState_TASK_STATE_QUEUED {
			f.t.Fatalf("release %d = %+v, %v", i, c, err)
		}
		if _, err := f.s.ReleaseTask(f.ctx, ref("w1", l)); errs.KindOf(err) != errs.FailedPrecondition {
			f.t.Fatalf("second release of the same lease: %v", err)
		}
	}
	for i := 1; i < maxAttempts; i++ {
		if _, err := f.s.FailTask(f.ctx, ref("w1", f.lease("w1")), store.Transient("x")); err != nil {
			f.t.Fatal(err)
		}
		f.clock.Advance(f.opts.Backoff(i))
	}
	if got := f.job(j.Id).State; got != pb.JobState_JOB_STATE_RUNNING {
		f.t.Errorf("job state = %v; releases must not count as failures", got)
	}
}

func testReleaseWorker(f *fixture) {
	j := f.create("a", 3)
	f.lease("w1")
	f.lease("w2")
	f.lease("w1")
	cs, err := f.s.ReleaseWorker(f.ctx, "w1")
	if err != nil || len(cs) != 2 {
		f.t.Fatalf("ReleaseWorker = %v, %v", cs, err)
	}
	if got := taskStates(f.tasks(j.Id)); got != "QLQW" {
		f.t.Errorf("states = %s, want QLQW", got)
	}
}

func testCancel(f *fixture) {
	j := f.create("a", 3)
	l := f.lease("w1")
	c, err := f.s.CancelJob(f.ctx, j.Id)
	if err != nil || !c.JobStateChanged || c.Job.State != pb.JobState_JOB_STATE_CANCELLED || c.Job.EndTime == nil {
		f.t.Fatalf("CancelJob = %+v, %v", c, err)
	}
	if got := taskStates(f.tasks(j.Id)); got != "CCCC" {
		f.t.Errorf("states = %s, want CCCC", got)
	}
	f.noLease("w2")
	hb, _ := f.s.ExtendLeases(f.ctx, "w1", []*pb.HeldLease{{TaskId: l.Lease.TaskId, Epoch: l.Lease.Epoch}})
	if len(hb.Revoked) != 1 {
		f.t.Errorf("heartbeat after cancel: revoked = %v, want the lease", hb.Revoked)
	}
	_, err = f.s.CompleteTask(f.ctx, ref("w1", l), nil)
	wantKind(f.t, "complete after cancel", err, errs.FailedPrecondition)
	_, err = f.s.CancelJob(f.ctx, j.Id)
	wantKind(f.t, "second cancel", err, errs.FailedPrecondition)
}

func testListJobs(f *fixture) {
	var ids []string
	for i := 0; i < 5; i++ {
		ids = append(ids, f.create(fmt.Sprint("job", i), 1).Id)
		f.clock.Advance(time.Second)
	}
	var got []string
	tok := ""
	for page := 0; ; page++ {
		jobs, next, err := f.s.ListJobs(f.ctx, 2, tok)
		if err != nil {
			f.t.Fatal(err)
		}
		if page > 3 || len(jobs) > 2 {
			f.t.Fatalf("page %d has %d jobs", page, len(jobs))
		}
		for _, j := range jobs {
			got = append(got, j.Id)
		}
		if next == "" {
			break
		}
		tok = next
	}
	want := []string{ids[4], ids[3], ids[2], ids[1], ids[0]}
	if fmt.Sprint(got) != fmt.Sprint(want) {
		f.t.Errorf("listed %v, want newest first %v", got, want)
	}
	// A job created between pages does not shift later pages.
	jobs, next, _ := f.s.ListJobs(f.ctx, 2, "")
	f.create("late", 1)
	jobs2, _, _ := f.s.ListJobs(f.ctx, 2, next)
	if len(jobs) != 2 || len(jobs2) != 2 || jobs2[0].Id != ids[2] {
		f.t.Errorf("second page after a new job = %v", jobs2)
	}
	_, _, err := f.s.ListJobs(f.ctx, 2, "garbage!")
	wantKind(f.t, "ListJobs with a bad token", err, errs.InvalidArgument)
	all, next, _ := f.s.ListJobs(f.ctx, 100, "")
	if len(all) != 6 || next != "" {
		f.t.Errorf("one big page: %d jobs, next %q", len(all), next)
	}
}

func testListTasks(f *fixture) {
	j := f.create("a", 4)
	var got []uint32
	tok := ""
	for {
		ts, next, err := f.s.ListTasks(f.ctx, j.Id, 2, tok)
		if err != nil {
			f.t.Fatal(err)
		}
		for _, t := range ts {
			got = append(got, t.Index)
		}
		if next == "" {
			break
		}
		tok = next
	}
	if fmt.Sprint(got) != "[0 1 2 3 4]" {
		f.t.Errorf("indices = %v", got)
	}
	_, _, err := f.s.ListTasks(f.ctx, j.Id, 2, "garbage!")
	wantKind(f.t, "ListTasks with a bad token", err, errs.InvalidArgument)
}

func testConcurrentLeases(f *fixture) {
	const tiles, workers = 40, 8
	j := f.create("a", tiles)
	var mu sync.Mutex
	seen := map[string]int{}
	var wg sync.WaitGroup
	for w := 0; w < workers; w++ {
		wg.Add(1)
		go func(w int) {
			defer wg.Done()
			id := fmt.Sprint("w", w)
			for {
				l, err := f.s.LeaseTask(f.ctx, id, store.WorkerPhases)
				if err != nil {
					f.t.Error(err)
					return
				}
				if l == nil {
					return
				}
				mu.Lock()
				seen[l.Lease.TaskId]++
				mu.Unlock()
				if _, err := f.s.CompleteTask(f.ctx, ref(id, l), []*pb.Artifact{artifact("tile.exr", l.Lease.TaskId)}); err != nil {
					f.t.Error(err)
				}
			}
		}(w)
	}
	wg.Wait()
	if len(seen) < tiles {
		f.t.Errorf("leased %d distinct tasks, want at least %d", len(seen), tiles)
	}
	for id, n := range seen {
		if n != 1 {
			f.t.Errorf("task %s leased %d times", id, n)
		}
	}
	// Workers may have stopped before the composite was queued; finish it.
	for {
		l, _ := f.s.LeaseTask(f.ctx, "w0", store.WorkerPhases)
		if l == nil {
			break
		}
		f.complete("w0", l)
	}
	if got := f.job(j.Id).State; got != pb.JobState_JOB_STATE_SUCCEEDED {
		f.t.Errorf("job state = %v", got)
	}
}
