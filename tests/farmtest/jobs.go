package farmtest

import (
	"context"
	"path/filepath"
	"slices"
	"strings"
	"testing"
	"time"

	"google.golang.org/protobuf/proto"

	"photonfarm/client"
	pb "photonfarm/proto/renderfarm/v1"
)

// LoadScene loads scenes/NAME through the client, uploading its meshes, and returns a copy
// the test may change.
func (f *Farm) LoadScene(t testing.TB, name string) *pb.Scene {
	t.Helper()
	ctx, cancel := context.WithTimeout(context.Background(), 30*time.Second)
	defer cancel()
	sc, err := f.Client.LoadSceneFile(ctx, filepath.Join(RepoRoot(), "scenes", name))
	if err != nil {
		t.Fatal(err)
	}
	return proto.Clone(sc).(*pb.Scene)
}

// TestScene loads scenes/test-small.json and changes its film and sampling: width x height
// pixels in tiles of side tile, spp samples, with a global photon map of 20,000 paths in
// two shards. The scene has no specular surface, so it gets no caustic map; the small
// global map keeps tests of tiles spending their time rendering.
func (f *Farm) TestScene(t testing.TB, width, height, tile, spp uint32) *pb.Scene {
	t.Helper()
	sc := f.LoadScene(t, "test-small.json")
	sc.Film = &pb.Film{Width: width, Height: height, TileSize: tile}
	sc.Sampling.SamplesPerPixel = spp
	sc.Photons = &pb.PhotonMapping{GlobalPhotons: 20000, PhotonsPerShard: 10000}
	return sc
}

// Render submits sc and waits up to timeout for the job to end; it fails the test unless
// the job succeeded.
func (f *Farm) Render(t testing.TB, sc *pb.Scene, timeout time.Duration) *pb.Job {
	t.Helper()
	job := f.Submit(t, sc)
	return f.Wait(t, job.GetId(), timeout)
}

// Submit submits sc and returns the new job.
func (f *Farm) Submit(t testing.TB, sc *pb.Scene) *pb.Job {
	t.Helper()
	ctx, cancel := context.WithTimeout(context.Background(), 30*time.Second)
	defer cancel()
	job, err := f.Client.Submit(ctx, sc)
	if err != nil {
		t.Fatalf("submit: %v", err)
	}
	return job
}

// Wait waits up to timeout for the job to end and fails the test unless it succeeded.
func (f *Farm) Wait(t testing.TB, jobID string, timeout time.Duration) *pb.Job {
	t.Helper()
	return f.WaitWatching(t, jobID, timeout, nil)
}

// WaitWatching is Wait that also hands each of the job's events to fn (if not nil).
func (f *Farm) WaitWatching(t testing.TB, jobID string, timeout time.Duration, fn func(*pb.WatchJobResponse)) *pb.Job {
	t.Helper()
	ctx, cancel := context.WithTimeout(context.Background(), timeout)
	defer cancel()
	job, err := f.Client.Watch(ctx, jobID, fn)
	if err != nil {
		last, _ := f.Client.GetJob(context.Background(), jobID)
		t.Fatalf("job %s: %v (last seen: %v)", jobID, err, last)
	}
	if job.GetState() != pb.JobState_JOB_STATE_SUCCEEDED {
		t.Fatalf("job %s ended %v: %s", jobID, job.GetState(), job.GetError())
	}
	return job
}

// Output downloads the named artifact ("image.exr", "preview.png") of a succeeded job.
func (f *Farm) Output(t testing.TB, job *pb.Job, name string) []byte {
	t.Helper()
	return f.OutputFrom(t, f.Client, job, name)
}

// OutputFrom is Output through another client (another replica's).
func (f *Farm) OutputFrom(t testing.TB, c *client.Client, job *pb.Job, name string) []byte {
	t.Helper()
	for _, a := range job.GetOutputs() {
		if a.GetName() == name {
			var b strings.Builder
			if _, err := c.Download(context.Background(), a.GetDigest(), &b); err != nil {
				t.Fatalf("download %s: %v", name, err)
			}
			return []byte(b.String())
		}
	}
	t.Fatalf("job %s has no %s output (outputs: %v)", job.GetId(), name, job.GetOutputs())
	return nil
}

// Tasks lists the job's tasks.
func (f *Farm) Tasks(t testing.TB, jobID string) []*pb.Task {
	t.Helper()
	tasks, err := f.Client.ListTasks(context.Background(), jobID)
	if err != nil {
		t.Fatalf("list tasks: %v", err)
	}
	return tasks
}

// TasksOf returns the tasks of one phase.
func TasksOf(tasks []*pb.Task, phase pb.Phase) []*pb.Task {
	return slices.DeleteFunc(slices.Clone(tasks), func(t *pb.Task) bool { return t.GetPhase() != phase })
}
