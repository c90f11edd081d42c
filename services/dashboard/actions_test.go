package dashboard_test

import (
	"encoding/json"
	"net/http"
	"slices"
	"testing"

	"photonfarm/contract/scene/scenetest"
	pb "photonfarm/proto/renderfarm/v1"
)

// TestRetryRequeueAndDeleteReachEveryOpenPage fails a job as bad input, then retries its
// task, requeues it after a cancel and deletes it through the dashboard's POSTs: each
// answer says what the coordinator did, refusals have their statuses, and two open
// /api/events streams (two tabs of the job list) see the job reopen and, deleted, go.
func TestRetryRequeueAndDeleteReachEveryOpenPage(t *testing.T) {
	f := newFarm(t)
	b := f.browser(clientToken)
	job, err := f.c.Submit(f.ctx, scenetest.Unlit(128, 128))
	must(t, err)
	w, err := f.workers.RegisterWorker(f.worker(), &pb.RegisterWorkerRequest{Hostname: "w"})
	must(t, err)
	l, err := f.workers.LeaseTask(f.worker(), &pb.LeaseTaskRequest{WorkerId: w.WorkerId})
	if err != nil || l.GetLease() == nil {
		t.Fatalf("lease: %v, %v; want a task", l, err)
	}
	_, err = f.workers.FailTask(f.worker(), &pb.FailTaskRequest{WorkerId: w.WorkerId, TaskId: l.GetLease().GetTaskId(),
		Epoch: l.GetLease().GetEpoch(), Error: "bad mesh", Kind: pb.FailureKind_FAILURE_KIND_BAD_INPUT})
	must(t, err)
	task := l.GetLease().GetTaskId()

	// stateIn is the job's state in a jobs-changed event, "" if it is not there.
	stateIn := func(data string) (state string, removed bool) {
		var ev struct {
			Jobs    []json.RawMessage
			Removed []string
		}
		must(t, json.Unmarshal([]byte(data), &ev))
		for _, raw := range ev.Jobs {
			var j pb.Job
			unmarshalInto(t, raw, &j)
			if j.Id == job.Id {
				state = j.State.String()
			}
		}
		return state, slices.Contains(ev.Removed, job.Id)
	}
	tabs := []*stream{f.openStream(b, "/api/events"), f.openStream(b, "/api/events")}
	waitAll := func(what string, ok func(state string, removed bool) bool) {
		t.Helper()
		for _, s := range tabs {
			s.until(what, func(ev event) bool { return ev.name == "jobs-changed" && ok(stateIn(ev.data)) })
		}
	}
	for _, s := range tabs {
		s.until("the job list", func(ev event) bool { return ev.name == "jobs" })
	}

	post := func(path string) response { return f.do(b, "POST", path, "{}") }
	jobPath := "/api/jobs/" + job.Id
	wantStatus(t, "retry of a task of another job", post("/api/jobs/j-other/tasks/"+task+"/retry"), http.StatusNotFound)
	wantStatus(t, "retry of an unknown task", post(jobPath+"/tasks/"+job.Id+".999/retry"), http.StatusNotFound)
	wantStatus(t, "requeue of an unknown job", post("/api/jobs/j-nope/requeue"), http.StatusNotFound)
	wantStatus(t, "delete of an unknown job", post("/api/jobs/j-nope/delete"), http.StatusNotFound)

	r := post(jobPath + "/tasks/" + task + "/retry")
	wantStatus(t, "retry", r, http.StatusOK)
	var answer struct{ Job, Task json.RawMessage }
	must(t, json.Unmarshal([]byte(r.Body), &answer))
	var gotJob pb.Job
	var gotTask pb.Task
	unmarshalInto(t, answer.Job, &gotJob)
	unmarshalInto(t, answer.Task, &gotTask)
	if gotJob.State != pb.JobState_JOB_STATE_QUEUED || gotTask.State != pb.TaskState_TASK_STATE_QUEUED || gotTask.Id != task {
		t.Fatalf("retry answer: job %v, task %v; want both queued", gotJob.State, &gotTask)
	}
	waitAll("the job queued again", func(state string, _ bool) bool { return state == "JOB_STATE_QUEUED" })
	wantStatus(t, "a second retry", post(jobPath+"/tasks/"+task+"/retry"), http.StatusConflict)
	wantStatus(t, "requeue of a queued job", post(jobPath+"/requeue"), http.StatusConflict)

	wantStatus(t, "cancel", post(jobPath+"/cancel"), http.StatusOK)
	waitAll("the job cancelled", func(state string, _ bool) bool { return state == "JOB_STATE_CANCELLED" })
	wantStatus(t, "requeue", post(jobPath+"/requeue"), http.StatusOK)
	waitAll("the job requeued", func(state string, _ bool) bool { return state == "JOB_STATE_QUEUED" })

	wantStatus(t, "delete", post(jobPath+"/delete"), http.StatusOK)
	waitAll("the job removed", func(_ string, removed bool) bool { return removed })
	wantStatus(t, "GET of the deleted job", f.do(b, "GET", jobPath, ""), http.StatusNotFound)
	r = f.do(b, "GET", "/api/jobs", "")
	wantStatus(t, "GET /api/jobs", r, http.StatusOK)
	var list struct{ Jobs []json.RawMessage }
	must(t, json.Unmarshal([]byte(r.Body), &list))
	if jobs := list.Jobs; len(jobs) != 0 {
		t.Errorf("GET /api/jobs after the delete lists %d jobs, want none", len(jobs))
	}
}
