package integration

import (
	"context"
	"testing"
	"time"

	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

// TestCancelStopsTheWorkersTaskWithinSeconds cancels a job while its only worker is deep
// in a tile that takes far longer than the cancel may: the worker must drop the tile
// (its lease is revoked at the next heartbeat) and take the next job's work at once, so a
// small job submitted after the cancel finishes long before that tile could have.
func TestCancelStopsTheWorkersTaskWithinSeconds(t *testing.T) {
	f := farmtest.StartFarm(t, nil)
	f.StartWorker(t).WorkerID(t, 15*time.Second)
	// One 64x64 tile at 512 samples a pixel and 64 gather rays a sample: over a minute on
	// one thread.
	long := f.Submit(t, f.TestScene(t, 64, 64, 64, 512))
	for deadline := time.Now().Add(60 * time.Second); ; time.Sleep(20 * time.Millisecond) {
		if time.Now().After(deadline) {
			t.Fatalf("the long job's tile was never leased: %v", f.Tasks(t, long.GetId()))
		}
		if tiles := farmtest.TasksOf(f.Tasks(t, long.GetId()), pb.Phase_PHASE_RENDER); len(tiles) == 1 &&
			tiles[0].GetState() == pb.TaskState_TASK_STATE_LEASED {
			break
		}
	}
	time.Sleep(500 * time.Millisecond) // well into the tile
	ctx, cancel := context.WithTimeout(context.Background(), 10*time.Second)
	defer cancel()
	cancelled := time.Now()
	if _, err := f.Client.Cancel(ctx, long.GetId()); err != nil {
		t.Fatal(err)
	}
	small := f.Render(t, f.TestScene(t, 16, 16, 16, 1), 60*time.Second)
	took := time.Since(cancelled)
	if took > 10*time.Second {
		t.Errorf("a 16x16 job took %s after the cancel: the worker kept rendering the cancelled tile", took)
	}
	if got, _ := f.Client.GetJob(ctx, long.GetId()); got.GetState() != pb.JobState_JOB_STATE_CANCELLED {
		t.Errorf("the cancelled job is %v", got.GetState())
	}
	for _, task := range f.Tasks(t, long.GetId()) {
		if task.GetState() == pb.TaskState_TASK_STATE_LEASED {
			t.Errorf("task %s of the cancelled job is still leased", task.GetId())
		}
	}
	t.Logf("job %s finished %s after the cancel of %s", small.GetId(), took.Round(time.Millisecond), long.GetId())
}
