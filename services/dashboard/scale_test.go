package dashboard_test

import (
	"net/http"
	"testing"
	"time"

	"photonfarm/contract/scene/scenetest"
	pb "photonfarm/proto/renderfarm/v1"
)

// TestReadsOfAFullFarm: with 100 jobs and over 10,000 tasks stored (one job of 10,000
// tiles), the list and the big job answer whole; the durations are logged, not asserted.
func TestReadsOfAFullFarm(t *testing.T) {
	if testing.Short() {
		t.Skip("stores 20,000 tasks")
	}
	f := newFarm(t)
	b := f.browser(clientToken)
	start := time.Now()
	for range 99 {
		if _, err := f.c.Submit(f.ctx, scenetest.Unlit(320, 320)); err != nil { // 100 tiles
			t.Fatal(err)
		}
	}
	big := scenetest.Unlit(1600, 1600)
	big.Film.TileSize = 16 // 100 x 100 tiles
	job, err := f.c.Submit(f.ctx, big)
	must(t, err)
	t.Logf("stored 100 jobs in %v", time.Since(start))

	start = time.Now()
	r := f.do(b, "GET", "/api/jobs", "")
	took := time.Since(start)
	wantStatus(t, "jobs", r, http.StatusOK)
	var jobs []*pb.Job
	decode(t, r.Body, map[string]any{"jobs": &jobs})
	if len(jobs) != 100 || jobs[0].Id != job.Id {
		t.Fatalf("%d jobs listed, the first %s; want 100, the big one first", len(jobs), jobs[0].Id)
	}
	t.Logf("GET /api/jobs: 100 jobs, %d bytes in %v", len(r.Body), took)

	start = time.Now()
	r = f.do(b, "GET", "/api/jobs/"+job.Id, "")
	took = time.Since(start)
	wantStatus(t, "big job", r, http.StatusOK)
	var tasks []*pb.Task
	var got pb.Job
	decode(t, r.Body, map[string]any{"job": &got, "tasks": &tasks})
	if len(tasks) != 10001 || tasks[10000].GetComposite() == nil {
		t.Fatalf("%d tasks, want 10,000 tiles and the composite", len(tasks))
	}
	t.Logf("GET /api/jobs/{id}: 10,001 tasks, %d bytes in %v", len(r.Body), took)

	start = time.Now()
	s := f.openStream(b, "/api/jobs/"+job.Id+"/events")
	if ev := s.next(); ev.name != "job" {
		t.Fatalf("first event %s", ev.name)
	}
	t.Logf("GET /api/jobs/{id}/events: the job event in %v", time.Since(start))
}
