package dashboard_test

import (
	"net/http"
	"net/url"
	"testing"
	"time"

	"photonfarm/contract/scene/scenetest"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/services/dashboard"
)

// TestReadsOfAFullFarm: with 100 jobs and over 10,000 tasks stored (one job of 10,000
// tiles), the list answers whole and the big job a page of its tasks at a time; the
// durations and sizes are logged, not asserted.
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
	var next string
	decode(t, r.Body, map[string]any{"job": &got, "tasks": &tasks, "nextPageToken": &next})
	if len(tasks) != dashboard.TasksPage || next == "" {
		t.Fatalf("%d tasks and next page %q, want the first %d and a token", len(tasks), next, dashboard.TasksPage)
	}
	t.Logf("GET /api/jobs/{id}: the job and its first %d tasks, %d bytes in %v", len(tasks), len(r.Body), took)

	// The rest, a page at a time.
	all, pages, largest, start := tasks, 1, len(r.Body), time.Now()
	for next != "" {
		r = f.do(b, "GET", "/api/jobs/"+job.Id+"/tasks?pageToken="+url.QueryEscape(next), "")
		wantStatus(t, "a page of tasks", r, http.StatusOK)
		decode(t, r.Body, map[string]any{"tasks": &tasks, "nextPageToken": &next})
		if len(tasks) > dashboard.TasksPage {
			t.Fatalf("a page of %d tasks, over %d", len(tasks), dashboard.TasksPage)
		}
		all, pages, largest = append(all, tasks...), pages+1, max(largest, len(r.Body))
	}
	if len(all) != 10001 || all[10000].GetComposite() == nil {
		t.Fatalf("%d tasks, want 10,000 tiles and the composite", len(all))
	}
	t.Logf("GET /api/jobs/{id}/tasks: 10,001 tasks in %d pages of at most %d bytes, %v",
		pages, largest, time.Since(start).Round(time.Millisecond))

	start = time.Now()
	s := f.openStream(b, "/api/jobs/"+job.Id+"/events")
	if ev := s.next(); ev.name != "job" {
		t.Fatalf("first event %s", ev.name)
	}
	t.Logf("GET /api/jobs/{id}/events: the job event in %v", time.Since(start))
}
