package builder_test

import (
	"bytes"
	"context"
	"io"
	"os"
	"strings"
	"testing"
	"time"

	"google.golang.org/protobuf/proto"

	"photonfarm/contract/rules"
	"photonfarm/contract/scene"
	"photonfarm/contract/scene/scenetest"
	"photonfarm/contract/tasks"
	"photonfarm/coordinator/blobstore"
	"photonfarm/coordinator/builder"
	"photonfarm/coordinator/clock"
	"photonfarm/coordinator/events"
	"photonfarm/coordinator/photonmap"
	"photonfarm/coordinator/planner"
	"photonfarm/coordinator/service"
	"photonfarm/coordinator/store"
	"photonfarm/coordinator/store/memstore"
	pb "photonfarm/proto/renderfarm/v1"
)

// fixture is a task service over an in-memory store and a real blob store, with a
// builder running against it.
type fixture struct {
	t       *testing.T
	ctx     context.Context
	st      store.Store
	svc     *service.Service
	blobs   *blobstore.Store
	dir     string // the blob store's
	scratch string // the builder's
}

func newFixture(t *testing.T, build func(photonmap.Output, []photonmap.Source) (int64, error)) *fixture {
	t.Helper()
	dir := t.TempDir()
	bs, err := blobstore.New(dir, 0)
	if err != nil {
		t.Fatal(err)
	}
	st := memstore.New(store.Options{Clock: clock.Real{}, LeaseDuration: 5 * time.Second})
	svc := service.New(service.Config{Store: st, Blobs: bs, Events: events.NewBroker(0)})
	ctx, cancel := context.WithTimeout(context.Background(), 30*time.Second)
	scratch := t.TempDir()
	b := builder.New(builder.Config{Tasks: svc, Blobs: bs, Build: build, ScratchDir: scratch, HeartbeatInterval: 50 * time.Millisecond})
	done := make(chan error, 1)
	go func() { done <- b.Run(ctx) }()
	t.Cleanup(func() {
		cancel()
		svc.Shutdown()
		if err := <-done; err != nil {
			t.Errorf("Run: %v", err)
		}
	})
	return &fixture{t: t, ctx: ctx, st: st, svc: svc, blobs: bs, dir: dir, scratch: scratch}
}

// createJob plans a Valid scene with `shards` global-map shards of 1000 photons, without
// final gathering: the build is followed by the tiles directly.
func (f *fixture) createJob(shards int) *pb.Job {
	return f.createJobIn(shards, pb.IndirectMode_INDIRECT_MODE_PHOTON_MAP)
}

// createJobIn is createJob in the given indirect mode (final gathering adds a precompute
// task per shard and a merge).
func (f *fixture) createJobIn(shards int, mode pb.IndirectMode) *pb.Job {
	f.t.Helper()
	sc := scenetest.Valid(8, 8)
	sc.Photons = &pb.PhotonMapping{GlobalPhotons: uint64(1000 * shards), PhotonsPerShard: 1000}
	sc.Indirect = &pb.Indirect{Mode: mode}
	sc = scene.Defaults(sc)
	// Workers' leases need the scene in the blob store, as SubmitJob leaves it.
	data, err := proto.Marshal(sc)
	if err != nil {
		f.t.Fatal(err)
	}
	stored, err := f.blobs.Put(f.ctx, bytes.NewReader(data), int64(len(data)), "")
	if err != nil {
		f.t.Fatal(err)
	}
	j, err := f.st.CreateJob(f.ctx, store.NewJob{DisplayName: "j", SceneDigest: stored.Digest,
		Width: 8, Height: 8, Tasks: planner.Plan(sc)})
	if err != nil {
		f.t.Fatal(err)
	}
	return j
}

// emit completes every emit shard of the job as a worker would, with data(i) as shard i.
func (f *fixture) emit(data func(i int, spec *pb.EmitPhotonsSpec) []byte) [][]byte {
	f.t.Helper()
	return f.completeEach(pb.ArtifactKind_ARTIFACT_KIND_PHOTON_SHARD, func(i int, t *pb.Task) []byte {
		if spec := t.GetEmitPhotons(); spec != nil {
			return data(i, spec)
		}
		return nil
	})
}

// completeEach leases the workers' tasks one at a time and completes each as a worker
// would, with data(i, task) stored as its artifact of the given kind, until data returns
// nil (a task of another kind: it must not have been leased) or there is nothing to
// lease. It returns what it stored.
func (f *fixture) completeEach(kind pb.ArtifactKind, data func(i int, t *pb.Task) []byte) [][]byte {
	f.t.Helper()
	var out [][]byte
	for i := 0; ; i++ {
		l, err := f.svc.Lease(f.ctx, "w1", store.WorkerPhases, 0)
		if err != nil {
			f.t.Fatal(err)
		}
		if l.GetLease() == nil {
			return out
		}
		b := data(i, l.GetTask())
		if b == nil {
			f.t.Fatalf("leased %v, want a task of the phase before the builder's or nothing", l.Task)
		}
		info, err := f.blobs.Put(f.ctx, bytes.NewReader(b), int64(len(b)), "")
		if err != nil {
			f.t.Fatal(err)
		}
		out = append(out, b)
		ref := store.LeaseRef{WorkerID: "w1", TaskID: l.Lease.TaskId, Epoch: l.Lease.Epoch}
		art := &pb.Artifact{Name: tasks.ArtifactName(kind), Digest: info.Digest, SizeBytes: info.Size}
		if err := f.svc.Complete(f.ctx, ref, []*pb.Artifact{art}); err != nil {
			f.t.Fatal(err)
		}
	}
}

// waitFor polls the job's build task until done says it is finished.
func (f *fixture) waitFor(jobID string, done func(build *pb.Task, job *pb.Job) bool) (*pb.Task, *pb.Job) {
	f.t.Helper()
	for deadline := time.Now().Add(10 * time.Second); time.Now().Before(deadline); time.Sleep(10 * time.Millisecond) {
		tasks, _, err := f.st.ListTasks(f.ctx, jobID, 1000, "")
		if err != nil {
			f.t.Fatal(err)
		}
		job, _ := f.st.GetJob(f.ctx, jobID)
		for _, t := range tasks {
			if t.GetBuildPhotonMap() != nil && done(t, job) {
				return t, job
			}
		}
	}
	f.t.Fatal("the builder did not get there within 10s")
	return nil, nil
}

func validShard(i int, spec *pb.EmitPhotonsSpec) []byte {
	var ps []photonmap.ShardPhoton
	for k := 0; k < 5; k++ {
		ps = append(ps, photonmap.ShardPhoton{Position: [3]float32{float32(i), float32(k), 0.5}, Power: [3]float32{1e-3, 2e-3, 3e-3}})
	}
	return photonmap.EncodeShard(photonmap.Global, spec.GetFirstPhoton(), spec.GetPhotonCount(), ps)
}

func TestBuilderMergesShardsIntoTheSnapshotTilesGet(t *testing.T) {
	f := newFixture(t, nil)
	j := f.createJob(3)
	shards := f.emit(validShard)
	if len(shards) != 3 {
		t.Fatalf("emitted %d shards, want 3", len(shards))
	}
	build, _ := f.waitFor(j.Id, func(b *pb.Task, _ *pb.Job) bool { return b.State == pb.TaskState_TASK_STATE_SUCCEEDED })
	if build.WorkerId != builder.DefaultWorkerID || build.Attempts != 1 || len(build.Outputs) != 1 || build.Outputs[0].Name != "photons.snapshot" {
		t.Fatalf("build task = %v", build)
	}
	var in []photonmap.Shard
	for _, s := range shards {
		in = append(in, photonmap.Shard{Data: s})
	}
	want, err := photonmap.Build(in)
	if err != nil {
		t.Fatal(err)
	}
	r, _, err := f.blobs.Open(f.ctx, build.Outputs[0].Digest)
	if err != nil {
		t.Fatal(err)
	}
	got, _ := io.ReadAll(r)
	r.Close()
	if !bytes.Equal(got, want) {
		t.Errorf("stored snapshot (%d bytes) differs from photonmap.Build of the shards in plan order (%d bytes)", len(got), len(want))
	}
	tile, err := f.svc.Lease(f.ctx, "w1", store.WorkerPhases, 0)
	if err != nil || tile.GetTask().GetRenderTile().GetPhotonSnapshot().GetDigest() != build.Outputs[0].Digest {
		t.Errorf("tile lease = %v, %v; want the snapshot", tile, err)
	}
}

func TestBuilderFailsTheJobAtOnceOnMalformedShards(t *testing.T) {
	f := newFixture(t, nil)
	j := f.createJob(2)
	f.emit(func(i int, spec *pb.EmitPhotonsSpec) []byte {
		if i == 1 {
			return []byte("not a shard at all")
		}
		return validShard(i, spec)
	})
	build, job := f.waitFor(j.Id, func(_ *pb.Task, job *pb.Job) bool { return store.Ended(job.State) })
	if job.State != pb.JobState_JOB_STATE_FAILED || build.State != pb.TaskState_TASK_STATE_FAILED {
		t.Fatalf("job %v, build %v; want both failed", job.State, build.State)
	}
	if !strings.Contains(build.Error, "shards[1]") || !strings.Contains(job.Error, build.Error) {
		t.Errorf("build error %q, job error %q; want the builder's error naming shards[1]", build.Error, job.Error)
	}
	// Bad input: one attempt, no retry, nobody blamed.
	bad := pb.FailureKind_FAILURE_KIND_BAD_INPUT
	if build.Attempts != 1 || build.FailureKind != bad || job.FailureKind != bad || len(job.BlockedWorkers) != 0 {
		t.Errorf("build took %d attempts, kinds %v / %v, blocked %v; want one attempt failed as bad input",
			build.Attempts, build.FailureKind, job.FailureKind, job.BlockedWorkers)
	}
}

func TestBuilderAbandonsABuildWhoseLeaseIsLost(t *testing.T) {
	release := make(chan struct{})
	started := make(chan struct{}, 1)
	f := newFixture(t, func(out photonmap.Output, _ []photonmap.Source) (int64, error) {
		started <- struct{}{}
		<-release
		n, err := out.WriteAt([]byte("late snapshot"), 0)
		return int64(n), err
	})
	j := f.createJob(1)
	f.emit(validShard)
	<-started
	if _, err := f.st.CancelJob(f.ctx, j.Id); err != nil {
		t.Fatal(err)
	}
	time.Sleep(200 * time.Millisecond) // a few heartbeats: the revocation is seen
	close(release)
	build, _ := f.waitFor(j.Id, func(b *pb.Task, _ *pb.Job) bool { return b.State == pb.TaskState_TASK_STATE_CANCELLED })
	time.Sleep(100 * time.Millisecond)
	if len(build.Outputs) != 0 {
		t.Errorf("cancelled build has outputs %v", build.Outputs)
	}
	if _, err := f.blobs.Stat(f.ctx, rules.DigestOf([]byte("late snapshot"))); err == nil {
		t.Error("the abandoned build's snapshot was stored")
	}
}

// A shard damaged on disk after its upload, in a way that still parses (a coordinate's
// byte flipped), was merged silently; the builder reads through the checked reader, so the
// job fails at once naming the shard and the damage.
func TestBuilderFailsTheJobWhenAShardIsDamagedOnDisk(t *testing.T) {
	f := newFixture(t, nil)
	j := f.createJob(3)
	var damaged string
	f.emit(func(i int, spec *pb.EmitPhotonsSpec) []byte {
		if i == 2 { // shard 1 is stored; the build waits for this last one
			prev := validShard(1, &pb.EmitPhotonsSpec{FirstPhoton: 1000, PhotonCount: 1000})
			damaged = rules.DigestOf(prev)
			prev[40+4] ^= 0x01 // the first photon's y, still a finite float
			if err := os.WriteFile(blobstore.PathIn(f.dir, damaged), prev, 0o644); err != nil {
				t.Fatal(err)
			}
		}
		return validShard(i, spec)
	})
	build, job := f.waitFor(j.Id, func(_ *pb.Task, job *pb.Job) bool { return store.Ended(job.State) })
	lost := pb.FailureKind_FAILURE_KIND_LOST_INPUT
	want := "the global photon shard of paths 1000+1000 of round 1: blob " + damaged + " is damaged in the coordinator's blob store"
	if job.State != pb.JobState_JOB_STATE_FAILED || build.FailureKind != lost || job.FailureKind != lost ||
		!strings.Contains(job.Error, want) || build.Attempts != 1 || len(job.BlockedWorkers) != 0 {
		t.Fatalf("job %v %v %q, build %v after %d attempts; want both failed at once as lost input with %q",
			job.State, job.FailureKind, job.Error, build.State, build.Attempts, want)
	}
}

func TestBuilderRefusesMorePhotonsThanASnapshotMayHoldSayingWhatToLower(t *testing.T) {
	const limit = 12 // each shard stores 5 photons: the third goes over
	f := newFixture(t, func(o photonmap.Output, s []photonmap.Source) (int64, error) { return photonmap.BuildTo(o, s, limit) })
	j := f.createJob(3)
	f.emit(validShard)
	build, job := f.waitFor(j.Id, func(_ *pb.Task, job *pb.Job) bool { return store.Ended(job.State) })
	bad := pb.FailureKind_FAILURE_KIND_BAD_INPUT
	want := "the photon maps store more than the 12 photons a snapshot may hold (scene_limits.max_snapshot_photons): " +
		"the global map's shards up to the global photon shard of paths 2000+1000 of round 1 store 15 photons from 3000 paths (0.005 a path); lower photons.global_photons"
	if job.State != pb.JobState_JOB_STATE_FAILED || build.FailureKind != bad || !strings.Contains(job.Error, want) {
		t.Fatalf("job %v %v %q; want it failed as bad input with %q", job.State, build.FailureKind, job.Error, want)
	}
}
