package dashboard_test

import (
	"bytes"
	"encoding/json"
	"net/http"
	"net/url"
	"strings"
	"testing"
	"time"

	"google.golang.org/grpc/codes"
	"google.golang.org/protobuf/encoding/protojson"

	"photonfarm/contract/scene/scenetest"
	"photonfarm/coordinator"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/services/dashboard"
)

// sceneJSON is a valid scene without photon maps (render tiles and a composite) in the
// format of scenes/*.json.
func sceneJSON(t *testing.T, width, height uint32) string {
	t.Helper()
	b, err := protojson.Marshal(scenetest.Unlit(width, height))
	must(t, err)
	return string(b)
}

// submit submits a scene through the dashboard and returns the job.
func (f *farm) submit(b *http.Client, scene string) *pb.Job {
	f.t.Helper()
	r := f.do(b, "POST", "/api/jobs", scene)
	wantStatus(f.t, "submit", r, http.StatusOK)
	job := &pb.Job{}
	decode(f.t, r.Body, map[string]any{"job": job})
	return job
}

func TestLoginChecksTheTokenWithTheCoordinator(t *testing.T) {
	f := newFarm(t)
	b := f.browser("")
	wantStatus(t, "login with a wrong token", f.do(b, "POST", "/api/login", `{"token": "nope"}`), http.StatusUnauthorized)
	wantStatus(t, "login with a worker token", f.do(b, "POST", "/api/login", `{"token": "`+workerToken+`"}`), http.StatusUnauthorized)
	wantStatus(t, "login with no token", f.do(b, "POST", "/api/login", `{"token": ""}`), http.StatusUnauthorized)
	wantStatus(t, "login with a token that is not one", f.do(b, "POST", "/api/login", `{"token": "a b\u00e9"}`), http.StatusUnauthorized)
	wantStatus(t, "login with a malformed body", f.do(b, "POST", "/api/login", `token=x`), http.StatusBadRequest)

	var session struct{ Authenticated, AuthRequired bool }
	r := f.do(b, "GET", "/api/session", "")
	wantStatus(t, "session", r, http.StatusOK)
	must(t, json.Unmarshal([]byte(r.Body), &session))
	if session.Authenticated || !session.AuthRequired {
		t.Errorf("session before login = %+v, want not authenticated, auth required", session)
	}

	r = f.do(b, "POST", "/api/login", `{"token": "`+clientToken+`"}`)
	wantStatus(t, "login with the client token", r, http.StatusOK)
	if r.Body != "{\"ok\":true}\n" {
		t.Errorf("login answer %q", r.Body)
	}
	var cookie *http.Cookie
	for _, c := range r.Cookies {
		if c.Name == dashboard.CookieName {
			cookie = c
		}
	}
	if cookie == nil || !cookie.HttpOnly || cookie.SameSite != http.SameSiteStrictMode || cookie.Path != "/" || cookie.Value != clientToken {
		t.Fatalf("login cookie = %+v, want farm_token, HttpOnly, SameSite=Strict, Path=/", cookie)
	}
	r = f.do(b, "GET", "/api/session", "")
	must(t, json.Unmarshal([]byte(r.Body), &session))
	if !session.Authenticated || !session.AuthRequired {
		t.Errorf("session after login = %+v, want authenticated", session)
	}
	wantStatus(t, "jobs after login", f.do(b, "GET", "/api/jobs", ""), http.StatusOK)

	wantStatus(t, "logout", f.do(b, "POST", "/api/logout", ""), http.StatusOK)
	wantStatus(t, "jobs after logout", f.do(b, "GET", "/api/jobs", ""), http.StatusUnauthorized)

	// A bearer header works as the cookie does (scripts, curl).
	req, _ := http.NewRequest("GET", f.url+"/api/jobs", nil)
	req.Header.Set("Authorization", "Bearer "+clientToken)
	resp, err := http.DefaultClient.Do(req)
	must(t, err)
	resp.Body.Close()
	if resp.StatusCode != http.StatusOK {
		t.Errorf("jobs with a bearer header: %d", resp.StatusCode)
	}
}

func TestEveryCallIsRefusedWithoutAValidToken(t *testing.T) {
	f := newFarm(t)
	job, err := f.c.Submit(f.ctx, scenetest.Unlit(16, 16))
	must(t, err)
	digest, err := f.c.UploadBytes(f.ctx, []byte("png bytes"))
	must(t, err)
	for _, token := range []string{"", "wrong", workerToken} {
		b := &http.Client{}
		for _, c := range []struct{ method, path, body string }{
			{"GET", "/api/jobs", ""},
			{"GET", "/api/jobs/" + job.Id, ""},
			{"GET", "/api/workers", ""},
			{"GET", "/api/blobs/" + digest + "?name=tile.png", ""},
			{"GET", "/api/events", ""},
			{"GET", "/api/jobs/" + job.Id + "/events", ""},
			{"POST", "/api/jobs", sceneJSON(t, 16, 16)},
			{"POST", "/api/jobs/" + job.Id + "/cancel", ""},
			{"POST", "/api/jobs/" + job.Id + "/priority", `{"priority": 3}`},
		} {
			req, _ := http.NewRequestWithContext(f.ctx, c.method, f.url+c.path, strings.NewReader(c.body))
			req.Header.Set("Content-Type", "application/json")
			if token != "" {
				req.AddCookie(&http.Cookie{Name: dashboard.CookieName, Value: token})
			}
			resp, err := b.Do(req)
			must(t, err)
			resp.Body.Close()
			// A worker token is refused as an unknown one is: the answer does not say
			// which tokens exist.
			want := http.StatusUnauthorized
			if token == workerToken && strings.HasPrefix(c.path, "/api/blobs/") {
				want = http.StatusOK // blobs are the workers' too
			}
			if resp.StatusCode != want {
				t.Errorf("%s %s with token %q: %d, want %d", c.method, c.path, token, resp.StatusCode, want)
			}
		}
	}
	// Nothing was done.
	jobs, err := f.c.ListJobs(f.ctx)
	must(t, err)
	if len(jobs) != 1 || jobs[0].State != pb.JobState_JOB_STATE_QUEUED || jobs[0].Priority != 0 {
		t.Errorf("jobs after refused calls: %v", jobs)
	}
}

func TestSubmitListCancelAndPriority(t *testing.T) {
	f := newFarm(t)
	b := f.browser(clientToken)
	r := f.do(b, "GET", "/api/jobs", "")
	wantStatus(t, "jobs", r, http.StatusOK)
	if r.Body != "{\"jobs\":[]}\n" {
		t.Errorf("no jobs: %q, want an empty list", r.Body)
	}

	first := f.submit(b, sceneJSON(t, 64, 64))
	second := f.submit(b, sceneJSON(t, 32, 32))
	if first.Id == "" || first.State != pb.JobState_JOB_STATE_QUEUED || first.Width != 64 {
		t.Fatalf("submitted job = %v", first)
	}
	var jobs []*pb.Job
	decode(t, f.do(b, "GET", "/api/jobs", "").Body, map[string]any{"jobs": &jobs})
	if len(jobs) != 2 || jobs[0].Id != second.Id || jobs[1].Id != first.Id {
		t.Fatalf("jobs = %v, want the two, newest first", jobs)
	}
	if len(jobs[1].Phases) == 0 {
		t.Errorf("listed job without phases: %v", jobs[1])
	}

	var job pb.Job
	var tasks []*pb.Task
	r = f.do(b, "GET", "/api/jobs/"+first.Id, "")
	wantStatus(t, "job", r, http.StatusOK)
	decode(t, r.Body, map[string]any{"job": &job, "tasks": &tasks})
	if job.Id != first.Id || len(tasks) != 4+1 { // 2x2 tiles of 32 and the composite
		t.Fatalf("job %s with %d tasks, want %s with 5", job.Id, len(tasks), first.Id)
	}
	for i, task := range tasks {
		if task.Index != uint32(i) {
			t.Errorf("task %d has index %d: not in plan order", i, task.Index)
		}
	}
	if rt := tasks[0].GetRenderTile().GetRect(); rt.GetWidth() != 32 || rt.GetHeight() != 32 {
		t.Errorf("first tile rect = %v", rt)
	}
	wantStatus(t, "unknown job", f.do(b, "GET", "/api/jobs/j-nope", ""), http.StatusNotFound)

	// Priority.
	r = f.do(b, "POST", "/api/jobs/"+first.Id+"/priority", `{"priority": 7}`)
	wantStatus(t, "priority", r, http.StatusOK)
	decode(t, r.Body, map[string]any{"job": &job})
	if job.Priority != 7 {
		t.Errorf("priority answer = %v, want priority 7", &job)
	}
	r = f.do(b, "POST", "/api/jobs/"+first.Id+"/priority", `{"priority": -3}`)
	wantStatus(t, "negative priority", r, http.StatusOK)
	wantStatus(t, "priority out of range", f.do(b, "POST", "/api/jobs/"+first.Id+"/priority", `{"priority": 5000}`), http.StatusBadRequest)
	wantStatus(t, "priority beyond int32", f.do(b, "POST", "/api/jobs/"+first.Id+"/priority", `{"priority": 1e12}`), http.StatusBadRequest)
	wantStatus(t, "priority not a number", f.do(b, "POST", "/api/jobs/"+first.Id+"/priority", `{"priority": "high"}`), http.StatusBadRequest)
	wantStatus(t, "priority missing", f.do(b, "POST", "/api/jobs/"+first.Id+"/priority", `{}`), http.StatusBadRequest)
	wantStatus(t, "priority of an unknown job", f.do(b, "POST", "/api/jobs/j-nope/priority", `{"priority": 1}`), http.StatusNotFound)
	got, err := f.c.GetJob(f.ctx, first.Id)
	must(t, err)
	if got.Priority != -3 {
		t.Errorf("stored priority %d, want -3", got.Priority)
	}

	// Cancel, and cancel again.
	r = f.do(b, "POST", "/api/jobs/"+first.Id+"/cancel", "")
	wantStatus(t, "cancel", r, http.StatusOK)
	decode(t, r.Body, map[string]any{"job": &job})
	if job.State != pb.JobState_JOB_STATE_CANCELLED {
		t.Errorf("cancel answer = %v, want CANCELLED", &job)
	}
	if !strings.Contains(r.Body, `"JOB_STATE_CANCELLED"`) {
		t.Errorf("cancel answer %q does not name the state as an enum string", r.Body)
	}
	wantStatus(t, "cancel an ended job", f.do(b, "POST", "/api/jobs/"+first.Id+"/cancel", ""), http.StatusConflict)
	wantStatus(t, "priority of an ended job", f.do(b, "POST", "/api/jobs/"+first.Id+"/priority", `{"priority": 1}`), http.StatusConflict)
	wantStatus(t, "cancel an unknown job", f.do(b, "POST", "/api/jobs/j-nope/cancel", ""), http.StatusNotFound)
}

func TestSubmitRefusesBadScenes(t *testing.T) {
	f := newFarm(t)
	b := f.browser(clientToken)
	var m map[string]any
	must(t, json.Unmarshal([]byte(sceneJSON(t, 16, 16)), &m))
	m["film"] = map[string]any{"width": 0, "height": 16}
	bad, _ := json.Marshal(m)
	r := f.do(b, "POST", "/api/jobs", string(bad))
	wantStatus(t, "zero width", r, http.StatusBadRequest)
	if !strings.Contains(r.Body, "film.width") {
		t.Errorf("zero width: %s, want the field named", r.Body)
	}
	r = f.do(b, "POST", "/api/jobs", `{"film": {"widht": 3}}`)
	wantStatus(t, "unknown field", r, http.StatusBadRequest)
	if !strings.Contains(r.Body, "widht") {
		t.Errorf("unknown field: %s, want it named", r.Body)
	}
	wantStatus(t, "not JSON", f.do(b, "POST", "/api/jobs", `{"film": `), http.StatusBadRequest)
	// A mesh named by path must come with the scene (uploads_test.go sends it).
	m["film"] = map[string]any{"width": 16, "height": 16}
	m["shapes"] = append(m["shapes"].([]any), map[string]any{"name": "m", "material": "white", "mesh": map[string]any{"path": "meshes/octahedron.obj"}})
	withPath, _ := json.Marshal(m)
	r = f.do(b, "POST", "/api/jobs", string(withPath))
	wantStatus(t, "mesh by path", r, http.StatusBadRequest)
	if !strings.Contains(r.Body, "names the file meshes/octahedron.obj, which was not sent with the scene (sent: no other file)") {
		t.Errorf("mesh by path: %s, want it to say why in the user's terms", r.Body)
	}

	big := bytes.Repeat([]byte(" "), int(dashboard.MaxSceneBody)+1)
	wantStatus(t, "a body over 64 MiB", f.do(b, "POST", "/api/jobs", string(big)), http.StatusRequestEntityTooLarge)
	jobs, err := f.c.ListJobs(f.ctx)
	if err != nil || len(jobs) != 0 {
		t.Errorf("jobs after bad submissions: %v, %v; want none", jobs, err)
	}
}

func TestBlobProxy(t *testing.T) {
	f := newFarm(t)
	b := f.browser(clientToken)
	data := bytes.Repeat([]byte("\x89PNG tile "), 300000) // several download chunks
	digest, err := f.c.UploadBytes(f.ctx, data)
	must(t, err)
	for name, ctype := range map[string]string{"tile.png": "image/png", "image.exr": "image/x-exr", "weird": "application/octet-stream"} {
		r := f.do(b, "GET", "/api/blobs/"+digest+"?name="+name, "")
		wantStatus(t, "blob "+name, r, http.StatusOK)
		if r.Body != string(data) {
			t.Errorf("blob %s: %d bytes, want the %d uploaded", name, len(r.Body), len(data))
		}
		if got := r.Header.Get("Content-Type"); got != ctype {
			t.Errorf("blob %s: Content-Type %q, want %q", name, got, ctype)
		}
		if cc := r.Header.Get("Cache-Control"); !strings.Contains(cc, "immutable") {
			t.Errorf("blob %s: Cache-Control %q, want immutable", name, cc)
		}
	}
	missing := "sha256:" + strings.Repeat("0", 64)
	wantStatus(t, "missing blob", f.do(b, "GET", "/api/blobs/"+missing+"?name=tile.png", ""), http.StatusNotFound)
	wantStatus(t, "malformed digest", f.do(b, "GET", "/api/blobs/sha256:xyz?name=tile.png", ""), http.StatusBadRequest)
}

func TestWorkersAreListed(t *testing.T) {
	f := newFarm(t)
	b := f.browser(clientToken)
	reg, err := f.workers.RegisterWorker(f.worker(), &pb.RegisterWorkerRequest{Hostname: "render-1", Cores: 8, Version: "v1"})
	must(t, err)
	var workers []*pb.WorkerInfo
	r := f.do(b, "GET", "/api/workers", "")
	wantStatus(t, "workers", r, http.StatusOK)
	decode(t, r.Body, map[string]any{"workers": &workers})
	if len(workers) != 1 || workers[0].Id != reg.WorkerId || workers[0].Hostname != "render-1" || workers[0].State != pb.WorkerState_WORKER_STATE_IDLE {
		t.Errorf("workers = %v", workers)
	}

	// Past a page, the answer holds the first page and the token of the next.
	for range dashboard.WorkersPage {
		_, err := f.workers.RegisterWorker(f.worker(), &pb.RegisterWorkerRequest{Hostname: "more"})
		must(t, err)
	}
	var next string
	r = f.do(b, "GET", "/api/workers", "")
	decode(t, r.Body, map[string]any{"workers": &workers, "nextPageToken": &next})
	if len(workers) != dashboard.WorkersPage || workers[0].Id != reg.WorkerId || next == "" {
		t.Fatalf("first page: %d workers from %s, next %q; want %d from %s and a token", len(workers), workers[0].Id, next, dashboard.WorkersPage, reg.WorkerId)
	}
	r = f.do(b, "GET", "/api/workers?pageToken="+url.QueryEscape(next), "")
	decode(t, r.Body, map[string]any{"workers": &workers, "nextPageToken": &next})
	if len(workers) != 1 || workers[0].Hostname != "more" || next != "" {
		t.Errorf("second page: %d workers, next %q; want the last one and no token", len(workers), next)
	}
}

func TestFarmEventsSendTheJobList(t *testing.T) {
	f := newFarm(t)
	b := f.browser(clientToken)
	s := f.openStream(b, "/api/events")
	if s.resp.StatusCode != http.StatusOK || !strings.HasPrefix(s.resp.Header.Get("Content-Type"), "text/event-stream") {
		t.Fatalf("GET /api/events: %d %q", s.resp.StatusCode, s.resp.Header.Get("Content-Type"))
	}
	ev := s.next()
	if ev.name != "jobs" || ev.data != `{"jobs":[]}` {
		t.Fatalf("first event %s %s, want the empty job list", ev.name, ev.data)
	}
	if ev = s.next(); ev.name != "workers" {
		t.Fatalf("second event %s, want workers", ev.name)
	}
	job := f.submit(b, sceneJSON(t, 16, 16))
	ev = s.until("a jobs-changed event with the new job", func(ev event) bool { return ev.name == "jobs-changed" })
	var jobs []*pb.Job
	var removed []string
	decode(t, ev.data, map[string]any{"jobs": &jobs, "removed": &removed})
	if len(jobs) != 1 || jobs[0].Id != job.Id || len(removed) != 0 {
		t.Fatalf("jobs-changed event %v, removed %v; want the new job", jobs, removed)
	}
	// A change (the cancel) is sent too; nothing is sent while nothing changes.
	wantStatus(t, "cancel", f.do(b, "POST", "/api/jobs/"+job.Id+"/cancel", ""), http.StatusOK)
	ev = s.until("a jobs-changed event with the job cancelled", func(ev event) bool { return ev.name == "jobs-changed" })
	decode(t, ev.data, map[string]any{"jobs": &jobs})
	if len(jobs) != 1 || jobs[0].State != pb.JobState_JOB_STATE_CANCELLED {
		t.Errorf("jobs-changed event after the cancel: %v", jobs)
	}
	s.until("a workers event", func(ev event) bool { return ev.name == "workers" })
	for range 2 {
		if ev := s.until("another workers event", func(ev event) bool { return ev.name != "" }); ev.name != "workers" {
			t.Errorf("a %s event although nothing changed: %s", ev.name, ev.data)
		}
	}
}

func TestJobEventsSendJobThenTasksThenEnd(t *testing.T) {
	f := newFarm(t)
	b := f.browser(clientToken)
	job := f.submit(b, sceneJSON(t, 64, 32))
	s := f.openStream(b, "/api/jobs/"+job.Id+"/events")
	if s.resp.StatusCode != http.StatusOK {
		t.Fatalf("GET job events: %d", s.resp.StatusCode)
	}
	ev := s.next()
	var got pb.Job
	var tasks []*pb.Task
	if ev.name != "job" {
		t.Fatalf("first event %q, want job", ev.name)
	}
	decode(t, ev.data, map[string]any{"job": &got, "tasks": &tasks})
	if got.Id != job.Id || len(tasks) != 3 {
		t.Fatalf("job event: %s with %d tasks, want %s with 3", got.Id, len(tasks), job.Id)
	}

	// A worker leases a task: a task event.
	reg, err := f.workers.RegisterWorker(f.worker(), &pb.RegisterWorkerRequest{Hostname: "w", Cores: 1})
	must(t, err)
	l, err := f.workers.LeaseTask(f.worker(), &pb.LeaseTaskRequest{WorkerId: reg.WorkerId})
	if err != nil || l.Lease == nil {
		t.Fatalf("lease: %v, %v", l, err)
	}
	ev = s.until("a task event", func(ev event) bool { return ev.name == "task" })
	var task pb.Task
	decode(t, ev.data, map[string]any{"job": &got, "task": &task})
	if task.Id != l.Lease.TaskId || task.State != pb.TaskState_TASK_STATE_LEASED || task.WorkerId != reg.WorkerId || got.Id != job.Id {
		t.Errorf("task event: %v of %s, want %s leased by %s", &task, got.Id, l.Lease.TaskId, reg.WorkerId)
	}

	// The job ends: an end event, then the stream closes.
	_, err = f.c.Cancel(f.ctx, job.Id)
	must(t, err)
	ev = s.until("the end event", func(ev event) bool { return ev.name == "end" })
	decode(t, ev.data, map[string]any{"job": &got})
	if got.State != pb.JobState_JOB_STATE_CANCELLED {
		t.Errorf("end event job %v, want CANCELLED", &got)
	}
	if !s.ended() {
		t.Error("the stream stayed open after the end event")
	}

	// A job that has ended: job and end at once.
	s = f.openStream(b, "/api/jobs/"+job.Id+"/events")
	if ev := s.next(); ev.name != "job" {
		t.Errorf("ended job: first event %s", ev.name)
	}
	if ev := s.next(); ev.name != "end" {
		t.Errorf("ended job: second event %s", ev.name)
	}
	if !s.ended() {
		t.Error("the stream of an ended job stayed open")
	}

	s = f.openStream(b, "/api/jobs/j-nope/events")
	if s.resp.StatusCode != http.StatusNotFound {
		t.Errorf("events of an unknown job: %d, want 404", s.resp.StatusCode)
	}
}

// TestJobEventsAreCoalesced: many task changes in a burst reach the browser as at most one
// update per interval, with each task's last state.
func TestJobEventsAreCoalesced(t *testing.T) {
	f := newFarm(t, func(_ *coordinator.Config, d *dashboard.Config) { d.JobUpdateEvery = 500 * time.Millisecond })
	b := f.browser(clientToken)
	job := f.submit(b, sceneJSON(t, 64, 64))
	s := f.openStream(b, "/api/jobs/"+job.Id+"/events")
	s.next() // job
	reg, err := f.workers.RegisterWorker(f.worker(), &pb.RegisterWorkerRequest{Hostname: "w", Cores: 1})
	must(t, err)
	// The same task (the first queued) is leased and released 8 times: 16 changes.
	var taskID string
	for range 8 {
		l, err := f.workers.LeaseTask(f.worker(), &pb.LeaseTaskRequest{WorkerId: reg.WorkerId})
		if err != nil || l.Lease == nil {
			t.Fatalf("lease: %v, %v", l, err)
		}
		taskID = l.Lease.TaskId
		_, err = f.workers.ReleaseTask(f.worker(), &pb.ReleaseTaskRequest{WorkerId: reg.WorkerId, TaskId: l.Lease.TaskId, Epoch: l.Lease.Epoch})
		must(t, err)
	}
	// They happen within an interval or two (no real worker is this fast, but the
	// test's calls are): a few events, the last with the last state.
	events := 0
	for {
		ev := s.until("task events", func(ev event) bool { return ev.name == "task" })
		var task pb.Task
		var got pb.Job
		decode(t, ev.data, map[string]any{"job": &got, "task": &task})
		events++
		if task.Id != taskID {
			t.Fatalf("task event of %s, want %s", task.Id, taskID)
		}
		if task.State == pb.TaskState_TASK_STATE_QUEUED && task.Attempts == 8 {
			break
		}
	}
	if events > 4 {
		t.Errorf("%d task events for 16 changes within about a second; want them coalesced (at most 2 a second here)", events)
	}
	t.Logf("16 changes sent as %d task events", events)
}

func TestAuthenticationOffLetsAnyTokenIn(t *testing.T) {
	f := newFarm(t, noAuth())
	b := f.browser("")
	var session struct{ Authenticated, AuthRequired bool }
	must(t, json.Unmarshal([]byte(f.do(b, "GET", "/api/session", "").Body), &session))
	if !session.Authenticated || session.AuthRequired {
		t.Errorf("session without auth = %+v, want authenticated, not required", session)
	}
	wantStatus(t, "login with an empty token", f.do(b, "POST", "/api/login", `{"token": ""}`), http.StatusOK)
	wantStatus(t, "login with any token", f.do(b, "POST", "/api/login", `{"token": "anything"}`), http.StatusOK)
	wantStatus(t, "jobs", f.do(b, "GET", "/api/jobs", ""), http.StatusOK)
}

func TestSecurityHeadersAndStaticFiles(t *testing.T) {
	f := newFarm(t)
	b := f.browser("")
	for _, path := range []string{"/", "/index.html", "/api/jobs", "/api/nope"} {
		r := f.do(b, "GET", path, "")
		if got := r.Header.Get("Content-Security-Policy"); got != "default-src 'self'" {
			t.Errorf("%s: Content-Security-Policy %q", path, got)
		}
		if got := r.Header.Get("X-Content-Type-Options"); got != "nosniff" {
			t.Errorf("%s: X-Content-Type-Options %q", path, got)
		}
	}
	r := f.do(b, "GET", "/", "")
	if r.StatusCode != http.StatusOK || !strings.Contains(r.Body, "<html") || !strings.HasPrefix(r.Header.Get("Content-Type"), "text/html") {
		t.Errorf("GET /: %d %q %.100q", r.StatusCode, r.Header.Get("Content-Type"), r.Body)
	}
	wantStatus(t, "unknown API path", f.do(b, "GET", "/api/nope", ""), http.StatusNotFound)
	wantStatus(t, "unknown API path with a method", f.do(b, "DELETE", "/api/jobs", ""), http.StatusNotFound)
}

func TestErrorMapping(t *testing.T) {
	for code, want := range map[codes.Code]int{
		codes.OK:                 200,
		codes.InvalidArgument:    400,
		codes.Unauthenticated:    401,
		codes.PermissionDenied:   403,
		codes.NotFound:           404,
		codes.FailedPrecondition: 409,
		codes.ResourceExhausted:  413,
		codes.Unavailable:        503,
		codes.Internal:           500,
		codes.AlreadyExists:      500,
		codes.DeadlineExceeded:   500,
		codes.Unknown:            500,
	} {
		if got := dashboard.HTTPStatus(code); got != want {
			t.Errorf("HTTPStatus(%v) = %d, want %d", code, got, want)
		}
	}
}
