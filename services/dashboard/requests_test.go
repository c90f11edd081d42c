package dashboard_test

import (
	"context"
	"io"
	"net/http"
	"strings"
	"testing"
	"time"

	"photonfarm/coordinator"
	"photonfarm/services/dashboard"
)

// post sends body to path as contentType with the extra headers and a session cookie for
// token (none if "").
func (f *farm) post(path, contentType, token, body string, headers map[string]string) response {
	f.t.Helper()
	req, err := http.NewRequestWithContext(f.ctx, http.MethodPost, f.url+path, strings.NewReader(body))
	must(f.t, err)
	req.Header.Set("Content-Type", contentType)
	for k, v := range headers {
		req.Header.Set(k, v)
	}
	if token != "" {
		req.AddCookie(&http.Cookie{Name: dashboard.CookieName, Value: token})
	}
	resp, err := http.DefaultClient.Do(req)
	must(f.t, err)
	defer resp.Body.Close()
	data, _ := io.ReadAll(resp.Body)
	return response{StatusCode: resp.StatusCode, Header: resp.Header, Body: string(data)}
}

// TestStateChangesAreRefusedFromOtherOrigins posts to every state-changing endpoint as a
// page of another origin would (a form's text/plain body, or JSON with another port's
// Origin or a cross-site Sec-Fetch-Site), with the session cookie a browser would attach:
// each is refused and nothing changes; the same requests from the dashboard's own origin
// pass.
func TestStateChangesAreRefusedFromOtherOrigins(t *testing.T) {
	f := newFarm(t)
	job := f.submit(f.browser(clientToken), sceneJSON(t, 16, 16))
	own := strings.TrimSuffix(f.url, "/")
	otherPort := "http://127.0.0.1:1" // the same host, another port: same-site
	for _, c := range []struct{ path, body string }{
		{"/api/login", `{"token": "` + clientToken + `"}`},
		{"/api/logout", `{}`},
		{"/api/jobs", sceneJSON(t, 16, 16)},
		{"/api/jobs/" + job.Id + "/cancel", `{}`},
		{"/api/jobs/" + job.Id + "/priority", `{"priority": 7}`},
	} {
		for _, bad := range []struct {
			name, contentType string
			headers           map[string]string
			want              int
		}{
			{"a text/plain form", "text/plain", map[string]string{"Origin": own}, http.StatusUnsupportedMediaType},
			{"an urlencoded form", "application/x-www-form-urlencoded", nil, http.StatusUnsupportedMediaType},
			{"no content type", "", nil, http.StatusUnsupportedMediaType},
			{"JSON from another port", "application/json", map[string]string{"Origin": otherPort}, http.StatusForbidden},
			{"JSON from a same-site page", "application/json", map[string]string{"Sec-Fetch-Site": "same-site", "Origin": otherPort}, http.StatusForbidden},
			{"JSON from a cross-site page", "application/json", map[string]string{"Sec-Fetch-Site": "cross-site"}, http.StatusForbidden},
		} {
			r := f.post(c.path, bad.contentType, clientToken, c.body, bad.headers)
			if r.StatusCode != bad.want {
				t.Errorf("%s to %s: %d %s, want %d", bad.name, c.path, r.StatusCode, r.Body, bad.want)
			}
		}
	}
	jobs, err := f.c.ListJobs(f.ctx)
	must(t, err)
	if len(jobs) != 1 || jobs[0].GetPriority() != 0 || jobs[0].GetState() != job.GetState() {
		t.Fatalf("jobs after the refused posts: %v; want only %s, unchanged", jobs, job.Id)
	}
	sameOrigin := map[string]string{"Origin": own, "Sec-Fetch-Site": "same-origin"}
	wantStatus(t, "priority from the dashboard's page",
		f.post("/api/jobs/"+job.Id+"/priority", "application/json", clientToken, `{"priority": 7}`, sameOrigin), http.StatusOK)
	wantStatus(t, "login from the dashboard's page",
		f.post("/api/login", "application/json; charset=utf-8", "", `{"token": "`+clientToken+`"}`, sameOrigin), http.StatusOK)
}

// TestSubmitChecksTheTokenBeforeReadingTheBody starts posts without a valid token whose
// bodies never end: the dashboard must answer 401 at once rather than read them.
func TestSubmitChecksTheTokenBeforeReadingTheBody(t *testing.T) {
	f := newFarm(t)
	for _, token := range []string{"", "guessed", workerToken} {
		pr, pw := io.Pipe()
		go pw.Write([]byte(`{"name": "` + strings.Repeat("x", 64<<10))) // and no more
		ctx, cancel := context.WithTimeout(f.ctx, 10*time.Second)
		req, err := http.NewRequestWithContext(ctx, http.MethodPost, f.url+"/api/jobs", pr)
		must(t, err)
		req.Header.Set("Content-Type", "application/json")
		if token != "" {
			req.AddCookie(&http.Cookie{Name: dashboard.CookieName, Value: token})
		}
		resp, err := http.DefaultClient.Do(req)
		if err != nil {
			t.Errorf("token %q: %v (the dashboard waited for the body)", token, err)
		} else {
			resp.Body.Close()
			if resp.StatusCode != http.StatusUnauthorized {
				t.Errorf("token %q: %s, want 401", token, resp.Status)
			}
		}
		cancel()
		pw.Close()
	}
}

// TestRefusedTokensAreThrottledPerAddress presents wrong tokens (unknown ones and the
// worker token) at the login and in cookies: every refusal has the same answer, and once
// the address has had DefaultRefusedTokenBurst refused, its requests with a token answer
// 429 without reaching the coordinator, the right token too.
func TestRefusedTokensAreThrottledPerAddress(t *testing.T) {
	f := newFarm(t, func(_ *coordinator.Config, d *dashboard.Config) { d.RefusedTokenBurst = 0 })
	var answers []string
	for i := range dashboard.DefaultRefusedTokenBurst {
		var r response
		switch i % 3 {
		case 0:
			r = f.do(&http.Client{}, "POST", "/api/login", `{"token": "guess-`+string(rune('a'+i))+`"}`)
		case 1:
			r = f.do(&http.Client{}, "POST", "/api/login", `{"token": "`+workerToken+`"}`)
		case 2:
			r = f.post("/api/jobs/j-1/cancel", "application/json", workerToken, `{}`, nil)
		}
		wantStatus(t, "a wrong token", r, http.StatusUnauthorized)
		answers = append(answers, r.Body)
	}
	for _, a := range answers[1:] {
		if a != answers[0] {
			t.Errorf("refusals differ: %q and %q; want one answer for every refused token", answers[0], a)
		}
	}
	for _, r := range []response{
		f.do(&http.Client{}, "POST", "/api/login", `{"token": "`+clientToken+`"}`),
		f.post("/api/jobs/j-1/cancel", "application/json", clientToken, `{}`, nil),
	} {
		wantStatus(t, "a token after the burst", r, http.StatusTooManyRequests)
		if r.Header.Get("Retry-After") == "" {
			t.Error("429 without Retry-After")
		}
	}
	// A request without a token is not throttled: it guesses nothing.
	wantStatus(t, "the session without a token", f.do(&http.Client{}, "GET", "/api/session", ""), http.StatusOK)
}
