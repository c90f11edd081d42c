package integration

import (
	"bytes"
	"slices"
	"syscall"
	"testing"
	"time"

	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

// killWhileLeasing waits until worker w holds a lease on a task of the given phase,
// SIGKILLs it mid-task, and returns that task as it stood.
func killWhileLeasing(t *testing.T, f *farmtest.Farm, w *farmtest.Proc, jobID string, phase pb.Phase) *pb.Task {
	t.Helper()
	return killWhileLeasingOne(t, f, w, jobID, phase.String()+" task", func(task *pb.Task) bool { return task.GetPhase() == phase })
}

// killWhileLeasingOne waits until worker w holds a lease on a task that which accepts (what
// names such tasks), SIGKILLs it mid-task, and returns that task as it stood.
func killWhileLeasingOne(t *testing.T, f *farmtest.Farm, w *farmtest.Proc, jobID, what string, which func(*pb.Task) bool) *pb.Task {
	t.Helper()
	var victim *pb.Task
	for deadline := time.Now().Add(30 * time.Second); victim == nil; time.Sleep(5 * time.Millisecond) {
		if time.Now().After(deadline) {
			t.Fatalf("the worker leased no %s within 30s: %v", what, f.Tasks(t, jobID))
		}
		if w.Exited() {
			t.Fatalf("the worker exited on its own: %v", w.Err())
		}
		for _, task := range f.Tasks(t, jobID) {
			if which(task) && task.GetState() == pb.TaskState_TASK_STATE_LEASED && task.GetWorkerId() != "" {
				victim = task
				break
			}
		}
	}
	w.Kill(syscall.SIGKILL)
	<-w.Done()
	t.Logf("killed %s while it held %s (attempt %d)", victim.GetWorkerId(), victim.GetId(), victim.GetAttempts())
	return victim
}

// checkTakenOver checks that the task whose worker was killed succeeded after its lost
// lease, finished by the worker secondID.
func checkTakenOver(t *testing.T, tasks []*pb.Task, victim *pb.Task, secondID string) {
	t.Helper()
	i := slices.IndexFunc(tasks, func(x *pb.Task) bool { return x.GetId() == victim.GetId() })
	if i < 0 {
		t.Fatalf("task %s is gone from the job", victim.GetId())
	}
	got, killedID := tasks[i], victim.GetWorkerId()
	if got.GetState() != pb.TaskState_TASK_STATE_SUCCEEDED {
		t.Errorf("task %s is %v, want succeeded", got.GetId(), got.GetState())
	}
	if got.GetAttempts() < 2 {
		t.Errorf("task %s: %d attempts, want >= 2 (the lost lease counts)", got.GetId(), got.GetAttempts())
	}
	if got.GetWorkerId() == killedID || got.GetWorkerId() == "" || (secondID != "" && got.GetWorkerId() != secondID) {
		t.Errorf("task %s was finished by %q, want the second worker %q (the killed one was %q)", got.GetId(), got.GetWorkerId(), secondID, killedID)
	}
}

// checkSameAsUndisturbed renders sc again on the surviving worker and checks that the EXR
// has the same bytes as exr and that no task of the undisturbed run needed a second lease.
func checkSameAsUndisturbed(t *testing.T, f *farmtest.Farm, sc *pb.Scene, exr []byte, timeout time.Duration) {
	t.Helper()
	undisturbed := f.Render(t, sc, timeout)
	if again := f.Output(t, undisturbed, "image.exr"); !bytes.Equal(farmtest.WithoutRenderTime(again), farmtest.WithoutRenderTime(exr)) {
		t.Errorf("EXR after the kill (%d bytes) differs from the undisturbed render (%d bytes)", len(exr), len(again))
	}
	for _, task := range f.Tasks(t, undisturbed.GetId()) {
		if task.GetAttempts() != 1 {
			t.Errorf("undisturbed render: task %s took %d attempts", task.GetId(), task.GetAttempts())
		}
	}
}
