package storetest

import (
	"time"

	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

const builder = "coordinator-builder"

func testLeaseNeedsPhases(f *fixture) {
	f.create("a", 1)
	_, err := f.s.LeaseTask(f.ctx, "w1", nil)
	if err == nil {
		f.t.Fatal("LeaseTask with no phases succeeded")
	}
	if got := taskStates(f.tasks(f.job(f.create("b", 1).Id).Id)); got != "QW" {
		f.t.Errorf("states = %s; a refused lease must change nothing", got)
	}
}

func testLeasePhaseFilter(f *fixture) {
	a := f.createPhotonJob("a", 2, 1) // E E B R C
	b := f.createPhotonJob("b", 1, 1)
	// Workers take the emit shards of a, then of b; the builder finds nothing to build.
	for _, want := range []string{store.TaskID(a.Id, 0), store.TaskID(a.Id, 1)} {
		f.noLeaseOf(builder, store.BuilderPhases)
		if l := f.lease("w1"); l.Lease.TaskId != want || l.Task.GetEmitPhotons() == nil {
			f.t.Fatalf("leased %s (%v), want emit shard %s", l.Lease.TaskId, l.Task, want)
		} else {
			f.complete("w1", l, artifact("photons.shard", l.Lease.TaskId))
		}
	}
	// a's build is queued: workers skip it and take b's shard; the builder takes a's build.
	if l := f.lease("w2"); l.Lease.TaskId != store.TaskID(b.Id, 0) {
		f.t.Fatalf("worker leased %s, want b's emit shard (a's build is not for workers)", l.Lease.TaskId)
	} else {
		f.complete("w2", l, artifact("photons.shard", "b0"))
	}
	build := f.leaseOf(builder, store.BuilderPhases)
	if build.Lease.TaskId != store.TaskID(a.Id, 2) || build.Task.GetBuildPhotonMap() == nil || build.Task.WorkerId != builder {
		f.t.Fatalf("builder leased %v, want a's build task", build.Task)
	}
	// Now b's build is queued too; workers still get nothing.
	f.noLease("w1")
	if l := f.leaseOf(builder, store.BuilderPhases); l.Lease.TaskId != store.TaskID(b.Id, 1) {
		f.t.Fatalf("builder leased %s, want b's build", l.Lease.TaskId)
	}
	f.noLeaseOf(builder, store.BuilderPhases)
	// A lessee may take several phases at once, in queue order.
	f.complete(builder, build, artifact("photons.snapshot", "a"))
	all := []pb.Phase{pb.Phase_PHASE_BUILD, pb.Phase_PHASE_RENDER}
	if l := f.leaseOf("w3", all); l.Lease.TaskId != store.TaskID(a.Id, 3) {
		f.t.Errorf("leased %s, want a's tile", l.Lease.TaskId)
	}
}

func testPhotonPhasesOpenInOrder(f *fixture) {
	j := f.createPhotonJob("a", 2, 2) // E E B R R C
	if len(j.Phases) != 4 {
		f.t.Fatalf("phases = %v, want emit, build, render, composite", j.Phases)
	}
	for i, want := range []pb.Phase{pb.Phase_PHASE_EMIT, pb.Phase_PHASE_BUILD, pb.Phase_PHASE_RENDER, pb.Phase_PHASE_COMPOSITE} {
		if j.Phases[i].Phase != want {
			f.t.Errorf("phase %d = %v, want %v", i, j.Phases[i].Phase, want)
		}
	}
	states := func(want string) {
		f.t.Helper()
		if got := taskStates(f.tasks(j.Id)); got != want {
			f.t.Fatalf("states %s, want %s", got, want)
		}
	}
	opened := func(c store.Change, want bool) {
		f.t.Helper()
		if c.Queued != want {
			f.t.Errorf("completion opened the next phase: %v, want %v", c.Queued, want)
		}
	}
	states("QQWWWW")
	e0, e1 := f.lease("w1"), f.lease("w2")
	opened(f.complete("w2", e1, artifact("photons.shard", "e1")), false)
	states("LSWWWW")
	f.noLease("w2") // the build is not queued, and is not for workers anyway
	opened(f.complete("w1", e0, artifact("photons.shard", "e0")), true)
	states("SSQWWW")
	f.noLease("w1")
	build := f.leaseOf(builder, store.BuilderPhases)
	opened(f.complete(builder, build, artifact("photons.snapshot", "snap")), true)
	states("SSSQQW")
	r0, r1 := f.lease("w1"), f.lease("w2")
	for _, l := range []*store.Leased{e0, build, r1} {
		if want := map[pb.Phase][2]uint32{pb.Phase_PHASE_EMIT: {0, 2}, pb.Phase_PHASE_BUILD: {2, 3}, pb.Phase_PHASE_RENDER: {3, 5}}[l.Task.Phase]; l.StageStart != want[0] || l.StageEnd != want[1] {
			f.t.Errorf("lease of %s: stage [%d, %d), want [%d, %d)", l.Lease.TaskId, l.StageStart, l.StageEnd, want[0], want[1])
		}
	}
	opened(f.complete("w1", r0, artifact("tile.exr", "t0")), false)
	states("SSSSLW")
	opened(f.complete("w2", r1, artifact("tile.exr", "t1")), true)
	states("SSSSSQ")
	comp := f.lease("w1")
	c := f.complete("w1", comp, artifact("image.exr", "img"))
	if c.Job.State != pb.JobState_JOB_STATE_SUCCEEDED || len(c.Job.Outputs) != 1 || c.Job.Outputs[0].Name != "image.exr" {
		f.t.Errorf("job after composite = %v; want SUCCEEDED with the composite's outputs only", c.Job)
	}
	for _, ph := range c.Job.Phases {
		if ph.TasksSucceeded != ph.TasksTotal {
			f.t.Errorf("phase %v: %d/%d", ph.Phase, ph.TasksSucceeded, ph.TasksTotal)
		}
	}
}

func testJobWithoutPhotons(f *fixture) {
	j := f.create("a", 2) // R R C
	if got := taskStates(f.tasks(j.Id)); got != "QQW" {
		f.t.Errorf("states = %s, want the render phase queued at once", got)
	}
	f.noLeaseOf(builder, store.BuilderPhases)
	if l := f.lease("w1"); l.Task.GetRenderTile() == nil {
		f.t.Errorf("leased %v, want a tile", l.Task)
	}
}

func testBuildLeaseExpiry(f *fixture) {
	j := f.createPhotonJob("a", 1, 1)
	f.complete("w1", f.lease("w1"), artifact("photons.shard", "s0"))
	first := f.leaseOf(builder, store.BuilderPhases)
	f.clock.Advance(leaseDuration)
	if cs, err := f.s.ExpireLeases(f.ctx); err != nil || len(cs) != 1 {
		f.t.Fatalf("ExpireLeases = %v, %v", cs, err)
	}
	f.noLease("w1") // an expired build goes back to the builder, never to a worker
	again := f.leaseOf(builder, store.BuilderPhases)
	if again.Lease.TaskId != first.Lease.TaskId || again.Lease.Epoch <= first.Lease.Epoch {
		f.t.Fatalf("re-lease %v after %v", again.Lease, first.Lease)
	}
	_, err := f.s.CompleteTask(f.ctx, ref(builder, first), nil)
	wantKind(f.t, "complete under the expired build lease", err, errs.FailedPrecondition)
	f.clock.Advance(time.Second)
	f.complete(builder, again, artifact("photons.snapshot", "snap"))
	if got := taskStates(f.tasks(j.Id)); got != "SSQW" {
		f.t.Errorf("states = %s, want SSQW", got)
	}
}
