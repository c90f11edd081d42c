package service_test

import (
	"bytes"
	"fmt"
	"os"
	"strings"
	"testing"

	"google.golang.org/grpc/codes"

	"photonfarm/contract/scene/scenetest"
	"photonfarm/coordinator/blobstore"
	"photonfarm/coordinator/photonmap"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// Lost inputs: a blob a task reads that is missing from the blob store, or damaged there,
// fails the task's job at once with a message naming the blob and what it holds, and
// leasing goes on with the other jobs.

// lose removes the stored blob digest, as a coordinator started on another data folder
// finds it.
func (f *farm) lose(digest string) {
	f.t.Helper()
	if err := os.Remove(blobstore.PathIn(f.blobDir, digest)); err != nil {
		f.t.Fatal(err)
	}
}

// truncate cuts the stored blob digest to half its size, as a disk might damage it.
func (f *farm) truncate(digest string) {
	f.t.Helper()
	path := blobstore.PathIn(f.blobDir, digest)
	st, err := os.Stat(path)
	if err != nil {
		f.t.Fatal(err)
	}
	if err := os.Truncate(path, st.Size()/2); err != nil {
		f.t.Fatal(err)
	}
}

// wantLostInput checks that job failed as lost input with an error naming what and the
// blob digest, saying how it was lost.
func (f *farm) wantLostInput(jobID, what, digest, how string) {
	f.t.Helper()
	got, err := f.jobs.GetJob(f.ctx, &pb.GetJobRequest{JobId: jobID})
	if err != nil {
		f.t.Fatal(err)
	}
	j := got.Job
	if j.State != pb.JobState_JOB_STATE_FAILED || j.FailureKind != pb.FailureKind_FAILURE_KIND_LOST_INPUT ||
		!strings.Contains(j.Error, what+": blob "+digest+" "+how) || len(j.BlockedWorkers) != 0 {
		f.t.Fatalf("job = %s %v %q (blocked %v); want FAILED as lost input with %q naming the blob and %q",
			j.State, j.FailureKind, j.Error, j.BlockedWorkers, what, how)
	}
}

func TestLostSceneFailsItsJobAndLeasingGoesOn(t *testing.T) {
	f := newFarm(t)
	lostJob := f.submit(scenetest.Unlit(32, 32))
	other := f.submit(scenetest.Unlit(64, 32))
	f.lose(lostJob.SceneDigest)
	w := f.register()

	l := f.lease(w) // the older job's tile came first; now the other job's does
	if l.Task.JobId != other.Id {
		t.Fatalf("leased %s, want a task of the job whose scene is there (%s)", l.Task.Id, other.Id)
	}
	f.wantLostInput(lostJob.Id, "the scene", lostJob.SceneDigest, "is not in the coordinator's blob store")
}

func TestDamagedSceneFailsTheCompositeNamingIt(t *testing.T) {
	f := newFarm(t)
	_, w, l := f.leased(scenetest.Unlit(32, 32)) // one tile, then the composite
	f.complete(w, l, "tile.exr", "tile")
	f.truncate(l.SceneDigest)

	r, err := f.workers.LeaseTask(f.ctx, &pb.LeaseTaskRequest{WorkerId: w})
	if err != nil || r.GetLease() != nil {
		t.Fatalf("LeaseTask = %v, %v; want nothing left to do and no error", r, err)
	}
	f.wantLostInput(l.Task.JobId, "the scene", l.SceneDigest, "is damaged in the coordinator's blob store")
}

func TestLostTileFailsTheCompositeNamingTheTile(t *testing.T) {
	f := newFarm(t)
	_, w, first := f.leased(scenetest.Unlit(64, 32)) // two tiles
	f.complete(w, first, "tile.exr", "tile 0")
	second := f.lease(w)
	tile := f.complete(w, second, "tile.exr", "tile 1")
	f.lose(tile.Digest)

	if r, err := f.workers.LeaseTask(f.ctx, &pb.LeaseTaskRequest{WorkerId: w}); err != nil || r.GetLease() != nil {
		t.Fatalf("LeaseTask = %v, %v; want nothing left to do and no error", r, err)
	}
	f.wantLostInput(first.Task.JobId, "tile x 32 y 0 of round 1", tile.Digest, "is not in the coordinator's blob store")
}

func TestDamagedSnapshotFailsThePrecomputeNamingIt(t *testing.T) {
	f := newFarm(t)
	sc := scenetest.Valid(8, 8)
	sc.Photons = &pb.PhotonMapping{GlobalPhotons: 1000} // final gathering: a precompute task
	_, w, l := f.leased(sc)
	shard := photonmap.EncodeShard(photonmap.Global, 0, 1000, []photonmap.ShardPhoton{{Position: [3]float32{1, 2, 3}}})
	f.complete(w, l, "photons.shard", string(shard))
	build, err := f.svc.Lease(f.ctx, builderID, store.BuilderPhases, 0)
	if err != nil || build.GetLease() == nil {
		t.Fatalf("builder lease = %v, %v", build, err)
	}
	data, err := photonmap.Build([]photonmap.Shard{{Data: shard}})
	if err != nil {
		t.Fatal(err)
	}
	snap := f.upload(data)
	snap.Name = "photons.snapshot"
	ref := store.LeaseRef{WorkerID: builderID, TaskID: build.Lease.TaskId, Epoch: build.Lease.Epoch}
	if err := f.svc.Complete(f.ctx, ref, []*pb.Artifact{snap}); err != nil {
		t.Fatal(err)
	}
	f.truncate(snap.Digest)

	if r, err := f.workers.LeaseTask(f.ctx, &pb.LeaseTaskRequest{WorkerId: w}); err != nil || r.GetLease() != nil {
		t.Fatalf("LeaseTask = %v, %v; want nothing left to do and no error", r, err)
	}
	f.wantLostInput(l.Task.JobId, "the photon snapshot of round 1", snap.Digest, "is damaged in the coordinator's blob store")
}

func TestDamagedBlobIsAnErrorBeforeAnyByte(t *testing.T) {
	f := newFarm(t)
	data := bytes.Repeat([]byte("tile"), 1<<20) // four download chunks
	a := f.upload(data)
	f.truncate(a.Digest)

	stream, err := f.blobs.DownloadBlob(f.ctx, &pb.DownloadBlobRequest{Digest: a.Digest})
	if err != nil {
		t.Fatal(err)
	}
	msg, err := stream.Recv()
	wantCode(t, fmt.Sprintf("first DownloadBlob message (%d bytes)", len(msg.GetChunk())), err, codes.DataLoss, "")
	_, err = f.blobs.GetBlobInfo(f.ctx, &pb.GetBlobInfoRequest{Digest: a.Digest})
	wantCode(t, "GetBlobInfo", err, codes.DataLoss, "")

	// Uploading it again repairs it.
	f.upload(data)
	got, _, err := f.download(a.Digest)
	if err != nil || !bytes.Equal(got, data) {
		t.Fatalf("download after uploading again: %d bytes, %v", len(got), err)
	}
	if info, err := f.blobs.GetBlobInfo(f.ctx, &pb.GetBlobInfoRequest{Digest: a.Digest}); err != nil || info.SizeBytes != int64(len(data)) {
		t.Errorf("GetBlobInfo after uploading again = %v, %v", info, err)
	}
}
