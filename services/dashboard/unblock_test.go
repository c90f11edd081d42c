package dashboard_test

import (
	"encoding/json"
	"net/http"
	"testing"

	"photonfarm/contract/scene/scenetest"
	pb "photonfarm/proto/renderfarm/v1"
)

// TestUnblockUpdatesEveryOpenJobPage blocks a worker from a job the way the coordinator
// does (three failed attempts), then unblocks it through POST /api/jobs/{id}/unblock: the
// answer and both open streams of the job's page (two tabs) show no blocked worker.
func TestUnblockUpdatesEveryOpenJobPage(t *testing.T) {
	f := newFarm(t)
	b := f.browser(clientToken)
	job, err := f.c.Submit(f.ctx, scenetest.Unlit(256, 256)) // 16 tiles of the default 64 pixels
	must(t, err)
	bad, err := f.workers.RegisterWorker(f.worker(), &pb.RegisterWorkerRequest{Hostname: "flaky"})
	must(t, err)
	_, err = f.workers.RegisterWorker(f.worker(), &pb.RegisterWorkerRequest{Hostname: "healthy"}) // live, so the job does not fail
	must(t, err)
	for i := range 3 {
		l, err := f.workers.LeaseTask(f.worker(), &pb.LeaseTaskRequest{WorkerId: bad.WorkerId})
		if err != nil || l.GetLease() == nil {
			t.Fatalf("lease %d: %v, %v; want a task", i, l, err)
		}
		_, err = f.workers.FailTask(f.worker(), &pb.FailTaskRequest{WorkerId: bad.WorkerId, TaskId: l.GetLease().GetTaskId(),
			Epoch: l.GetLease().GetEpoch(), Error: "out of memory"})
		must(t, err)
	}

	blockedIn := func(data string) []*pb.BlockedWorker {
		var ev struct{ Job json.RawMessage }
		must(t, json.Unmarshal([]byte(data), &ev))
		var j pb.Job
		unmarshalInto(t, ev.Job, &j)
		return j.BlockedWorkers
	}
	tabs := []*stream{f.openStream(b, "/api/jobs/"+job.Id+"/events"), f.openStream(b, "/api/jobs/"+job.Id+"/events")}
	for i, s := range tabs {
		ev := s.until("the job event", func(ev event) bool { return ev.name == "job" })
		if got := blockedIn(ev.data); len(got) != 1 || got[0].WorkerId != bad.WorkerId {
			t.Fatalf("tab %d: blocked workers %v, want %s alone", i, got, bad.WorkerId)
		}
	}

	wantStatus(t, "unblock without a body", f.do(b, "POST", "/api/jobs/"+job.Id+"/unblock", ""), http.StatusBadRequest)
	wantStatus(t, "unblock of an unknown job", f.do(b, "POST", "/api/jobs/j-nope/unblock", `{"workerId": "`+bad.WorkerId+`"}`), http.StatusNotFound)
	r := f.do(b, "POST", "/api/jobs/"+job.Id+"/unblock", `{"workerId": "`+bad.WorkerId+`"}`)
	wantStatus(t, "unblock", r, http.StatusOK)
	if got := blockedIn(r.Body); len(got) != 0 {
		t.Errorf("unblock answer: blocked workers %v, want none", got)
	}
	for i, s := range tabs {
		s.until("an update without the blocked worker", func(ev event) bool {
			return ev.name != "" && ev.data != "" && len(blockedIn(ev.data)) == 0
		})
		t.Logf("tab %d saw the worker unblocked", i)
	}
	if got, err := f.c.GetJob(f.ctx, job.Id); err != nil || len(got.BlockedWorkers) != 0 {
		t.Errorf("the coordinator's job: %v, %v; want no blocked worker", got.GetBlockedWorkers(), err)
	}
}
