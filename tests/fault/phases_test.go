package fault

import (
	"context"
	"fmt"
	"strings"
	"testing"
	"time"

	"photonfarm/client"
	"photonfarm/contract/tasks"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

// currentPhase is the first phase of the job with a task not yet succeeded (phases run in
// order), or PHASE_UNSPECIFIED if there is none.
func currentPhase(job *pb.Job) pb.Phase {
	for _, p := range job.GetPhases() {
		if p.GetTasksSucceeded() < p.GetTasksTotal() {
			return p.GetPhase()
		}
	}
	return pb.Phase_PHASE_UNSPECIFIED
}

// getJob reads the job; the trials poll it every few milliseconds.
func getJob(t *testing.T, f *farmtest.Farm, jobID string) *pb.Job {
	t.Helper()
	ctx, cancel := context.WithTimeout(context.Background(), 10*time.Second)
	defer cancel()
	job, err := f.Client.GetJob(ctx, jobID)
	if err != nil {
		t.Fatalf("get job %s: %v", jobID, err)
	}
	return job
}

// timeline is how long each phase of an undisturbed job lasted.
type timeline map[pb.Phase]time.Duration

func (tl timeline) String() string {
	var parts []string
	for p := pb.Phase_PHASE_EMIT; p <= pb.Phase_PHASE_COMPOSITE; p++ {
		if d, ok := tl[p]; ok {
			parts = append(parts, fmt.Sprintf("%s %s", tasks.Name(p), d.Round(time.Millisecond)))
		}
	}
	return strings.Join(parts, ", ")
}

// renderTimed renders sc undisturbed, polling the job to time its phases, and returns the
// final EXR and the phases' durations. A phase too short to be seen between two polls is
// missing from the timeline.
func renderTimed(t *testing.T, f *farmtest.Farm, sc *pb.Scene, timeout time.Duration) ([]byte, timeline) {
	t.Helper()
	job := f.Submit(t, sc)
	tl := timeline{}
	phase, since := pb.Phase_PHASE_UNSPECIFIED, time.Now()
	for deadline := time.Now().Add(timeout); !client.JobEnded(job.GetState()); time.Sleep(2 * time.Millisecond) {
		if time.Now().After(deadline) {
			t.Fatalf("job %s did not end within %s: %v", job.GetId(), timeout, job)
		}
		job = getJob(t, f, job.GetId())
		if p := currentPhase(job); p != phase {
			if phase != pb.Phase_PHASE_UNSPECIFIED {
				tl[phase] = time.Since(since)
			}
			phase, since = p, time.Now()
		}
	}
	done := f.Wait(t, job.GetId(), time.Second)
	return f.Output(t, done, "image.exr"), tl
}

// snapshot says where the job stands: the name of its phase ("ended" if it has ended) and
// a description with the phase's progress and the leases held, e.g. "render (5/12 done;
// leased: j.17 (render) by w-1a2b, j.18 (render) by w-3c4d)".
func snapshot(t *testing.T, f *farmtest.Farm, jobID string) (name, description string) {
	t.Helper()
	job := getJob(t, f, jobID)
	if client.JobEnded(job.GetState()) {
		return "ended", "ended: " + tasks.JobStateName(job.GetState())
	}
	phase := currentPhase(job)
	var done, total uint32
	for _, p := range job.GetPhases() {
		if p.GetPhase() == phase {
			done, total = p.GetTasksSucceeded(), p.GetTasksTotal()
		}
	}
	var leased []string
	for _, task := range f.Tasks(t, jobID) {
		if task.GetState() == pb.TaskState_TASK_STATE_LEASED {
			leased = append(leased, fmt.Sprintf("%s (%s) by %s", task.GetId(), tasks.Name(task.GetPhase()), task.GetWorkerId()))
		}
	}
	if len(leased) == 0 {
		leased = []string{"none"}
	}
	name = tasks.Name(phase)
	return name, fmt.Sprintf("%s (%d/%d done; leased: %s)", name, done, total, strings.Join(leased, ", "))
}
