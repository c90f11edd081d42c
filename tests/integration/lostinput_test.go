package integration

import (
	"context"
	"os"
	"path/filepath"
	"strings"
	"testing"
	"time"

	"photonfarm/coordinator/blobstore"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

// Lost inputs on real processes (issue 12, finding 4): a blob missing from the
// coordinator's store or damaged on its disk fails the job that needs it within seconds,
// naming the blob and what it holds, blames no worker, and leaves the other jobs running.

// lostInputFarm is a farm whose coordinator keeps its blobs under the returned folder.
func lostInputFarm(t *testing.T) (*farmtest.Farm, string) {
	t.Helper()
	data := filepath.Join(t.TempDir(), "data")
	return farmtest.StartFarm(t, []string{"--data-dir", data}), filepath.Join(data, "blobs")
}

// waitLostInput waits for job to fail and checks it failed as lost input within limit of
// start, with an error containing want, and no worker blocked.
func waitLostInput(t *testing.T, f *farmtest.Farm, jobID, want string, start time.Time, limit time.Duration) {
	t.Helper()
	ctx, cancel := context.WithTimeout(context.Background(), 2*time.Minute)
	defer cancel()
	job, err := f.Client.Watch(ctx, jobID, nil)
	if err != nil {
		t.Fatalf("watch %s: %v", jobID, err)
	}
	took := time.Since(start)
	t.Logf("job failed after %v: %s", took.Round(time.Millisecond), job.GetError())
	if job.GetState() != pb.JobState_JOB_STATE_FAILED || job.GetFailureKind() != pb.FailureKind_FAILURE_KIND_LOST_INPUT ||
		!strings.Contains(job.GetError(), want) || len(job.GetBlockedWorkers()) != 0 {
		t.Fatalf("job %s: %v %v %q, blocked %v; want FAILED as lost input with %q", jobID, job.GetState(),
			job.GetFailureKind(), job.GetError(), job.GetBlockedWorkers(), want)
	}
	if took > limit {
		t.Errorf("the job took %v to fail, want within %v", took, limit)
	}
}

func TestDamagedSceneFailsItsJobWithinSecondsAndOtherJobsRender(t *testing.T) {
	f, blobs := lostInputFarm(t)
	damaged := f.Submit(t, f.TestScene(t, 32, 32, 16, 1))
	digest := damaged.GetSceneDigest()
	if err := os.Truncate(blobstore.PathIn(blobs, digest), 10); err != nil {
		t.Fatal(err)
	}
	other := f.Submit(t, f.TestScene(t, 48, 32, 16, 1))
	start := time.Now()
	f.StartWorker(t)
	waitLostInput(t, f, damaged.GetId(), "the scene: blob "+digest+" is damaged in the coordinator's blob store", start, 10*time.Second)
	f.Wait(t, other.GetId(), 2*time.Minute)
}

// The coordinator restarted on another data folder has none of the blobs its jobs need.
func TestJobsWhoseBlobsAreGoneFailNamingTheSceneAndTheMesh(t *testing.T) {
	f, blobs := lostInputFarm(t)
	noScene := f.Submit(t, f.TestScene(t, 32, 32, 16, 1))
	sc := f.TestScene(t, 48, 32, 16, 1)
	noMesh := f.Submit(t, sc)
	var mesh string
	for _, s := range sc.GetShapes() {
		if m := s.GetMesh(); m != nil {
			mesh = m.GetDigest()
		}
	}
	for _, d := range []string{noScene.GetSceneDigest(), mesh} {
		if err := os.Remove(blobstore.PathIn(blobs, d)); err != nil {
			t.Fatal(err)
		}
	}
	start := time.Now()
	f.StartWorker(t)
	// The coordinator finds the scene missing at lease time; the worker finds the mesh
	// missing when it builds the scene.
	waitLostInput(t, f, noScene.GetId(), "the scene: blob "+noScene.GetSceneDigest()+" is not in the coordinator's blob store", start, 10*time.Second)
	waitLostInput(t, f, noMesh.GetId(), `shapes[3].mesh.digest: cannot load mesh "meshes/octahedron.obj": blob `+mesh+" is not in the coordinator's blob store", start, 10*time.Second)
	f.Wait(t, f.Submit(t, f.TestScene(t, 16, 16, 16, 1)).GetId(), 2*time.Minute)
}
