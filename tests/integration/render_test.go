package integration

import (
	"bytes"
	"slices"
	"syscall"
	"testing"
	"time"

	pb "photonfarm/proto/renderfarm/v1"
)

// The scenes these tests render: scenes/test-small.json at a larger size. A tile of the
// stitch scene takes tens of milliseconds on one thread, so that both workers get tiles;
// a tile of the lease scene takes a few hundred, so that a kill lands while a lease is
// held.
var (
	stitchScene = sceneSize{width: 192, height: 128, tile: 16, spp: 256} // 96 tiles, ~20 ms each
	leaseScene  = sceneSize{width: 96, height: 64, tile: 32, spp: 1536}  // 6 tiles, ~350 ms each
)

type sceneSize struct{ width, height, tile, spp uint32 }

func (f *farm) scene(s sceneSize) *pb.Scene { return f.testScene(s.width, s.height, s.tile, s.spp) }

// renderTasks returns the tasks of the render phase.
func renderTasks(tasks []*pb.Task) []*pb.Task {
	var out []*pb.Task
	for _, t := range tasks {
		if t.GetPhase() == pb.Phase_PHASE_RENDER {
			out = append(out, t)
		}
	}
	return out
}

func checkOutputs(t *testing.T, f *farm, job *pb.Job, s sceneSize) []byte {
	t.Helper()
	exr := f.output(job, "image.exr")
	if err := checkFinalEXR(exr, int(s.width), int(s.height), int(s.tile)); err != nil {
		t.Error(err)
	}
	w, h, err := pngSize(f.output(job, "preview.png"))
	if err != nil || w != int(s.width) || h != int(s.height) {
		t.Errorf("preview.png: %dx%d, %v; want %dx%d", w, h, err, s.width, s.height)
	}
	return exr
}

func TestTwoWorkersStitchBitIdenticalToOneWorker(t *testing.T) {
	// Two workers.
	two := startFarm(t)
	w1, w2 := two.startWorker(), two.startWorker()
	w1.workerID(t, 15*time.Second)
	w2.workerID(t, 15*time.Second)
	job := two.render(two.scene(stitchScene), 90*time.Second)
	exrTwo := checkOutputs(t, two, job, stitchScene)

	tasks := two.tasks(job.GetId())
	tiles := renderTasks(tasks)
	if want := int((stitchScene.width / stitchScene.tile) * (stitchScene.height / stitchScene.tile)); len(tiles) != want {
		t.Errorf("%d render tasks, want %d", len(tiles), want)
	}
	perWorker := map[string]int{}
	for _, task := range tasks {
		if task.GetState() != pb.TaskState_TASK_STATE_SUCCEEDED {
			t.Errorf("task %s is %v after the job succeeded", task.GetId(), task.GetState())
		}
		if task.GetPhase() == pb.Phase_PHASE_RENDER {
			perWorker[task.GetWorkerId()]++
		}
	}
	t.Logf("tiles per worker: %v", perWorker)
	if len(perWorker) != 2 || perWorker[""] != 0 {
		t.Errorf("tiles were finished by %v; want both workers", perWorker)
	}

	// One worker, a fresh farm.
	one := startFarm(t)
	one.startWorker()
	jobOne := one.render(one.scene(stitchScene), 90*time.Second)
	exrOne := checkOutputs(t, one, jobOne, stitchScene)
	if !bytes.Equal(exrTwo, exrOne) {
		t.Errorf("EXR from two workers (%d bytes) differs from the one from one worker (%d bytes)", len(exrTwo), len(exrOne))
	}
}

func TestKilledWorkerLeaseExpiresAndJobCompletes(t *testing.T) {
	f := startFarm(t)
	first := f.startWorker()
	sc := f.scene(leaseScene)
	job := f.submit(sc)

	// Wait until the worker holds a lease on a render tile, then kill it mid-tile.
	var victim *pb.Task
	deadline := time.Now().Add(30 * time.Second)
	for victim == nil {
		if time.Now().After(deadline) {
			t.Fatalf("the worker leased no render tile within 30s: %v", f.tasks(job.GetId()))
		}
		if first.exited() {
			t.Fatalf("the worker exited on its own: %v", first.err)
		}
		for _, task := range renderTasks(f.tasks(job.GetId())) {
			if task.GetState() == pb.TaskState_TASK_STATE_LEASED && task.GetWorkerId() != "" {
				victim = task
				break
			}
		}
		if victim == nil {
			time.Sleep(10 * time.Millisecond)
		}
	}
	first.kill(syscall.SIGKILL)
	<-first.done
	killedID := victim.GetWorkerId()
	t.Logf("killed %s while it held %s (attempt %d)", killedID, victim.GetId(), victim.GetAttempts())

	second := f.startWorker()
	secondID := second.workerID(t, 15*time.Second)
	done := f.wait(job.GetId(), 90*time.Second)
	exrAfterKill := checkOutputs(t, f, done, leaseScene)

	tasks := f.tasks(job.GetId())
	i := slices.IndexFunc(tasks, func(x *pb.Task) bool { return x.GetId() == victim.GetId() })
	if i < 0 {
		t.Fatalf("task %s is gone from the job", victim.GetId())
	}
	got := tasks[i]
	if got.GetState() != pb.TaskState_TASK_STATE_SUCCEEDED {
		t.Errorf("task %s is %v, want succeeded", got.GetId(), got.GetState())
	}
	if got.GetAttempts() < 2 {
		t.Errorf("task %s: %d attempts, want >= 2 (the lost lease counts)", got.GetId(), got.GetAttempts())
	}
	if got.GetWorkerId() == killedID || got.GetWorkerId() == "" || (secondID != "" && got.GetWorkerId() != secondID) {
		t.Errorf("task %s was finished by %q, want the second worker %q (the killed one was %q)", got.GetId(), got.GetWorkerId(), secondID, killedID)
	}

	// The same scene again, undisturbed, on the surviving worker: the same bytes.
	undisturbed := f.render(sc, 90*time.Second)
	if exr := f.output(undisturbed, "image.exr"); !bytes.Equal(exr, exrAfterKill) {
		t.Errorf("EXR after the kill (%d bytes) differs from the undisturbed render (%d bytes)", len(exrAfterKill), len(exr))
	}
	for _, task := range f.tasks(undisturbed.GetId()) {
		if task.GetAttempts() != 1 {
			t.Errorf("undisturbed render: task %s took %d attempts", task.GetId(), task.GetAttempts())
		}
	}
}
