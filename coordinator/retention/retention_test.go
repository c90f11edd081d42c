package retention_test

import (
	"context"
	"testing"
	"time"

	"google.golang.org/protobuf/proto"

	"photonfarm/contract/scene/scenetest"
	"photonfarm/coordinator/blobstore/blobtest"
	"photonfarm/coordinator/clock"
	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/retention"
	"photonfarm/coordinator/store"
	"photonfarm/coordinator/store/memstore"
	"photonfarm/coordinator/store/storetest"
	pb "photonfarm/proto/renderfarm/v1"
)

// TestSweepDeletesExpiredJobsAndTheBlobsOnlyTheyUsed: a job that ended 200 hours ago (the
// retention is a week) is deleted; then of the blobs older than the grace period, those
// no remaining job refers to (its scene, its task's output, an orphan) are deleted, and
// those the running job refers to (its scene, a mesh and a reference image its scene
// names, also named by the deleted job's scene, its task's output and the log of its
// task's failed attempt, Task.log) are kept, as is
// a fresh upload no job names yet and an old one just touched by a submit in flight.
func TestSweepDeletesExpiredJobsAndTheBlobsOnlyTheyUsed(t *testing.T) {
	ctx := context.Background()
	now := time.Now()
	clk := clock.NewFake(now.Add(-200 * time.Hour))
	st := memstore.New(store.Options{Clock: clk})
	blobs := blobtest.New(t)
	put := blobs.Put
	mesh, reference := put("a mesh"), put("a reference")
	sceneNaming := func(name string) string {
		t.Helper()
		sc := scenetest.Valid(8, 8)
		sc.Name = name
		sc.Shapes = append(sc.Shapes, &pb.Shape{Material: "white", Geometry: &pb.Shape_Mesh{Mesh: &pb.MeshFile{Path: "m.obj", Digest: mesh}}})
		sc.Progressive = &pb.Progressive{Reference: &pb.ReferenceImage{Path: "r.exr", Digest: reference}}
		b, err := proto.Marshal(sc)
		if err != nil {
			t.Fatal(err)
		}
		return put(string(b))
	}
	lease := func() *store.Leased {
		t.Helper()
		l, err := st.LeaseTask(ctx, "w1", store.WorkerPhases)
		if err != nil || l == nil {
			t.Fatalf("LeaseTask = %v, %v", l, err)
		}
		return l
	}
	create := func(name string) (j *pb.Job, tile, log string) {
		t.Helper()
		nj := storetest.TileJob(name, 1)
		nj.SceneDigest = sceneNaming(name)
		j, err := st.CreateJob(ctx, nj)
		if err != nil {
			t.Fatal(err)
		}
		l := lease()
		log = put("log of " + name)
		if _, err := st.FailTask(ctx, store.LeaseRef{WorkerID: "w1", TaskID: l.Lease.TaskId, Epoch: l.Lease.Epoch},
			store.Failure{Message: "flaky", Log: &pb.Artifact{Name: "task.log", Digest: log, SizeBytes: int64(len("log of " + name))}}); err != nil {
			t.Fatal(err)
		}
		clk.Advance(store.DefaultMaxRetryBackoff)
		l = lease()
		tile = put("tile of " + name)
		if _, err := st.CompleteTask(ctx, store.LeaseRef{WorkerID: "w1", TaskID: l.Lease.TaskId, Epoch: l.Lease.Epoch},
			[]*pb.Artifact{{Name: "tile.exr", Digest: tile, SizeBytes: int64(len("tile of " + name))}}); err != nil {
			t.Fatal(err)
		}
		return j, tile, log
	}
	old, oldTile, oldLog := create("old")
	if _, err := st.CancelJob(ctx, old.Id); err != nil {
		t.Fatal(err)
	}
	clk.Advance(200 * time.Hour)
	live, liveTile, liveLog := create("live")
	orphan, inFlight := put("an orphan"), put("uploaded for a submit in flight")

	// Everything but the fresh upload is two days old.
	blobs.Age(now.Add(-48*time.Hour), mesh, reference, old.SceneDigest, oldTile, oldLog, live.SceneDigest, liveTile, liveLog, orphan, inFlight)
	fresh := put("a fresh upload")
	if _, err := blobs.Touch(ctx, inFlight); err != nil { // what SubmitJob does
		t.Fatal(err)
	}

	r, err := retention.New(retention.Config{Store: st, Blobs: blobs.Store, Clock: clk}).Sweep(ctx)
	if err != nil {
		t.Fatal(err)
	}
	t.Logf("sweep: %+v", r)
	if _, err := st.GetJob(ctx, old.Id); errs.KindOf(err) != errs.NotFound {
		t.Errorf("the job that ended 200 h ago: %v, want it deleted", err)
	}
	if _, err := st.GetJob(ctx, live.Id); err != nil {
		t.Errorf("the live job: %v", err)
	}
	for d, kept := range map[string]bool{old.SceneDigest: false, oldTile: false, oldLog: false, orphan: false,
		live.SceneDigest: true, liveTile: true, liveLog: true, mesh: true, reference: true, fresh: true, inFlight: true} {
		_, err := blobs.Stat(ctx, d)
		if got := err == nil; got != kept {
			t.Errorf("blob %s kept = %v, want %v", d[:15], got, kept)
		}
	}
	if r.Jobs != 1 || r.Blobs != 4 {
		t.Errorf("report %+v, want 1 job and 4 blobs deleted", r)
	}
}

// TestADeletedJobsBlobsGoAfterTheGrace: DeleteJob removes a job at once, but its blobs
// (its scene, its tasks' outputs) are the blob collection's: a sweep keeps them while they
// are younger than the grace and deletes them after, unless another job names them.
func TestADeletedJobsBlobsGoAfterTheGrace(t *testing.T) {
	for _, tt := range []struct {
		name   string
		finish bool // the job ends before it is deleted
	}{{"DeletedWhileRunning", false}, {"DeletedAfterItEnded", true}} {
		t.Run(tt.name, func(t *testing.T) {
			ctx := context.Background()
			now := time.Now()
			clk := clock.NewFake(now)
			st := memstore.New(store.Options{Clock: clk})
			blobs := blobtest.New(t)
			b, err := proto.Marshal(scenetest.Valid(8, 8))
			if err != nil {
				t.Fatal(err)
			}
			scene := blobs.Put(string(b)) // both jobs render it
			mk := func(name string) *pb.Job {
				t.Helper()
				nj := storetest.TileJob(name, 1)
				nj.SceneDigest = scene
				j, err := st.CreateJob(ctx, nj)
				if err != nil {
					t.Fatal(err)
				}
				return j
			}
			doomed := mk("doomed")
			l, err := st.LeaseTask(ctx, "w1", store.WorkerPhases)
			if err != nil || l == nil {
				t.Fatalf("LeaseTask = %v, %v", l, err)
			}
			tile := blobs.Put("tile of doomed")
			ref := store.LeaseRef{WorkerID: "w1", TaskID: l.Lease.TaskId, Epoch: l.Lease.Epoch}
			if _, err := st.CompleteTask(ctx, ref, []*pb.Artifact{{Name: "tile.exr", Digest: tile, SizeBytes: 14}}); err != nil {
				t.Fatal(err)
			}
			if tt.finish {
				if _, err := st.CancelJob(ctx, doomed.Id); err != nil {
					t.Fatal(err)
				}
			}
			other := mk("other")
			if _, err := st.DeleteJob(ctx, doomed.Id); err != nil {
				t.Fatal(err)
			}
			sweep := func() {
				t.Helper()
				if _, err := retention.New(retention.Config{Store: st, Blobs: blobs.Store, Clock: clk}).Sweep(ctx); err != nil {
					t.Fatal(err)
				}
			}
			kept := func(when string, want map[string]bool) {
				t.Helper()
				for d, keep := range want {
					if _, err := blobs.Stat(ctx, d); (err == nil) != keep {
						t.Errorf("%s: blob %s kept = %v, want %v", when, d[:15], err == nil, keep)
					}
				}
			}
			sweep()
			kept("within the grace", map[string]bool{tile: true, scene: true})
			blobs.Age(now.Add(-48*time.Hour), tile, scene)
			sweep()
			kept("after the grace", map[string]bool{tile: false, scene: true}) // the other job renders the scene
			if _, err := st.DeleteJob(ctx, other.Id); err != nil {
				t.Fatal(err)
			}
			sweep()
			kept("after the other job's delete", map[string]bool{scene: false})
		})
	}
}
