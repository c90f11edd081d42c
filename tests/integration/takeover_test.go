package integration

import (
	"bytes"
	"slices"
	"syscall"
	"testing"
	"time"

	pb "photonfarm/proto/renderfarm/v1"
)

// tasksOf returns the tasks of one phase.
func tasksOf(tasks []*pb.Task, phase pb.Phase) []*pb.Task {
	return slices.DeleteFunc(slices.Clone(tasks), func(t *pb.Task) bool { return t.GetPhase() != phase })
}

// killWhileLeasing waits until worker w holds a lease on a task of the given phase,
// SIGKILLs it mid-task, and returns that task as it stood.
func (f *farm) killWhileLeasing(t *testing.T, w *proc, jobID string, phase pb.Phase) *pb.Task {
	t.Helper()
	var victim *pb.Task
	for deadline := time.Now().Add(30 * time.Second); victim == nil; time.Sleep(5 * time.Millisecond) {
		if time.Now().After(deadline) {
			t.Fatalf("the worker leased no %v task within 30s: %v", phase, f.tasks(jobID))
		}
		if w.exited() {
			t.Fatalf("the worker exited on its own: %v", w.err)
		}
		for _, task := range tasksOf(f.tasks(jobID), phase) {
			if task.GetState() == pb.TaskState_TASK_STATE_LEASED && task.GetWorkerId() != "" {
				victim = task
				break
			}
		}
	}
	w.kill(syscall.SIGKILL)
	<-w.done
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
func (f *farm) checkSameAsUndisturbed(t *testing.T, sc *pb.Scene, exr []byte, timeout time.Duration) {
	t.Helper()
	undisturbed := f.render(sc, timeout)
	if again := f.output(undisturbed, "image.exr"); !bytes.Equal(again, exr) {
		t.Errorf("EXR after the kill (%d bytes) differs from the undisturbed render (%d bytes)", len(exr), len(again))
	}
	for _, task := range f.tasks(undisturbed.GetId()) {
		if task.GetAttempts() != 1 {
			t.Errorf("undisturbed render: task %s took %d attempts", task.GetId(), task.GetAttempts())
		}
	}
}
