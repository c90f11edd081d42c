package integration

import (
	"strings"
	"testing"
	"time"

	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

// A worker whose cache cannot hold the round's photon snapshot fails the tasks that need
// it as resource exhaustion: it is not blocked, pauses before leasing again, and another
// worker renders them, so the job succeeds.
func TestAWorkerWithAFullCacheIsNotBlockedAndTheJobCompletes(t *testing.T) {
	f := farmtest.StartFarm(t, nil)
	job := f.Submit(t, f.TestScene(t, 64, 64, 16, 1))
	small := f.StartWorker(t, "--cache-max-bytes", "8K") // the scene and the mesh, not the snapshot
	deadline := time.Now().Add(time.Minute)
	for !strings.Contains(small.LogTail(50), "pausing before the next lease") {
		if time.Now().After(deadline) {
			t.Fatalf("the small-cache worker never paused after a resource exhaustion; its log:\n%s", small.LogTail(30))
		}
		time.Sleep(50 * time.Millisecond)
	}
	f.StartWorker(t)
	done := f.Wait(t, job.GetId(), 2*time.Minute)
	if len(done.GetBlockedWorkers()) != 0 {
		t.Errorf("blocked workers %v; a full cache blames no worker", done.GetBlockedWorkers())
	}
	exhausted := 0
	for _, task := range f.Tasks(t, job.GetId()) {
		if task.GetFailureKind() == pb.FailureKind_FAILURE_KIND_RESOURCE_EXHAUSTED {
			exhausted++
			if !strings.Contains(task.GetError(), "the photon snapshot of round 1: cannot cache blob") || !strings.Contains(task.GetError(), "--cache-max-bytes") {
				t.Errorf("task %s: error %q, want it to name the snapshot and the cache's size", task.GetId(), task.GetError())
			}
		}
	}
	if exhausted == 0 {
		t.Error("no task failed as resource exhaustion: the small cache was never full")
	}
}
