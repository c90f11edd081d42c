package service_test

import (
	"fmt"
	"testing"
	"time"

	"google.golang.org/protobuf/proto"

	"photonfarm/contract/scene/scenetest"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

const builderID = "coordinator-builder"

func (f *farm) complete(worker string, l *pb.LeaseTaskResponse, name string, data string) *pb.Artifact {
	f.t.Helper()
	a := f.upload([]byte(data))
	a.Name = name
	if _, err := f.workers.CompleteTask(f.ctx, &pb.CompleteTaskRequest{WorkerId: worker, TaskId: l.Lease.TaskId, Epoch: l.Lease.Epoch, Outputs: []*pb.Artifact{a}}); err != nil {
		f.t.Fatalf("CompleteTask %s: %v", l.Lease.TaskId, err)
	}
	return a
}

func (f *farm) noWorkerLease(worker string) {
	f.t.Helper()
	if r, err := f.workers.LeaseTask(f.ctx, &pb.LeaseTaskRequest{WorkerId: worker}); err != nil || r.GetLease() != nil {
		f.t.Fatalf("LeaseTask = %v, %v; want nothing for a worker", r, err)
	}
}

func TestPhotonJobFillsBuildShardsAndTileSnapshots(t *testing.T) {
	f := newFarm(t)
	sc := scenetest.Valid(32, 64) // two tiles
	sc.Photons = &pb.PhotonMapping{GlobalPhotons: 2500, PhotonsPerShard: 1000}
	sc.Indirect = &pb.Indirect{Mode: pb.IndirectMode_INDIRECT_MODE_PHOTON_MAP} // no precompute
	job := f.submit(sc)
	if len(job.Phases) != 4 || job.Phases[0].Phase != pb.Phase_PHASE_EMIT || job.Phases[0].TasksTotal != 3 ||
		job.Phases[1].Phase != pb.Phase_PHASE_BUILD || job.Phases[1].TasksTotal != 1 {
		t.Fatalf("phases = %v, want 3 emit shards, a build, tiles and a composite", job.Phases)
	}
	w := f.register()

	// Emit shards go to workers, finished out of order.
	var leases []*pb.LeaseTaskResponse
	for i := 0; i < 3; i++ {
		l := f.lease(w)
		if e := l.Task.GetEmitPhotons(); e == nil || e.FirstPhoton != uint64(1000*i) || e.TotalPhotons != 2500 {
			t.Fatalf("lease %d = %v, want emit shard %d", i, l.Task, i)
		}
		leases = append(leases, l)
	}
	shards := make([]*pb.Artifact, 3)
	for _, i := range []int{2, 0, 1} {
		shards[i] = f.complete(w, leases[i], "photons.shard", fmt.Sprint("shard ", i))
	}
	// The build is queued, but never for a worker.
	f.noWorkerLease(w)

	build, err := f.svc.Lease(f.ctx, builderID, store.BuilderPhases, 0)
	if err != nil || build.GetLease() == nil {
		t.Fatalf("builder lease = %v, %v", build, err)
	}
	spec := build.Task.GetBuildPhotonMap()
	if spec == nil || len(spec.Shards) != 3 {
		t.Fatalf("build spec = %v, want 3 shards", build.Task)
	}
	for i, s := range spec.Shards {
		if s.Spec.GetFirstPhoton() != uint64(1000*i) || !proto.Equal(s.Shard, shards[i]) {
			t.Errorf("shard %d = %v, want plan order with the uploaded artifact %v", i, s, shards[i])
		}
	}
	snap := f.upload([]byte("snapshot"))
	snap.Name = "photons.snapshot"
	ref := store.LeaseRef{WorkerID: builderID, TaskID: build.Lease.TaskId, Epoch: build.Lease.Epoch}
	if err := f.svc.Complete(f.ctx, ref, []*pb.Artifact{snap}); err != nil {
		t.Fatalf("builder Complete: %v", err)
	}

	// Each tile learns the snapshot; the composite still learns its tiles.
	for i := 0; i < 2; i++ {
		l := f.lease(w)
		if l.Task.GetRenderTile() == nil || !proto.Equal(l.Task.GetRenderTile().GetPhotonSnapshot(), snap) {
			t.Fatalf("tile lease %d = %v, want the snapshot %v", i, l.Task, snap)
		}
		f.complete(w, l, "tile.exr", fmt.Sprint("tile ", i))
	}
	if comp := f.lease(w); len(comp.Task.GetComposite().GetTiles()) != 2 {
		t.Errorf("composite = %v", comp.Task)
	}
}

func TestBuilderLeaseWaitsForShardsAndEndsOnTimeout(t *testing.T) {
	f := newFarm(t)
	sc := scenetest.Valid(8, 8)
	sc.Photons = &pb.PhotonMapping{GlobalPhotons: 1000}
	_, w, l := f.leased(sc)

	got := make(chan *pb.LeaseTaskResponse, 1)
	go func() {
		r, err := f.svc.Lease(f.ctx, builderID, store.BuilderPhases, 20*time.Second)
		if err != nil {
			t.Error(err)
		}
		got <- r
	}()
	select {
	case r := <-got:
		t.Fatalf("builder leased %v before the shard was done", r)
	case <-time.After(50 * time.Millisecond):
	}
	f.complete(w, l, "photons.shard", "the shard")
	select {
	case r := <-got:
		if r.GetTask().GetBuildPhotonMap() == nil || len(r.Task.GetBuildPhotonMap().Shards) != 1 {
			t.Errorf("builder leased %v, want the build with one shard", r.GetTask())
		}
	case <-time.After(10 * time.Second):
		t.Fatal("the builder's long poll did not wake when the build was queued")
	}
	if r, err := f.svc.Lease(f.ctx, builderID, store.BuilderPhases, 10*time.Millisecond); err != nil || r.GetLease() != nil {
		t.Errorf("second builder lease = %v, %v; want nothing after the wait", r, err)
	}
}
