package main

import (
	"context"
	"io"
	"log/slog"
	"net/http"
	"strings"
	"testing"
	"time"

	"photonfarm/coordinator"
	"photonfarm/coordinator/coordinatortest"
	"photonfarm/tests/farmtest"
)

func TestDashboardVerbServesUntilInterrupted(t *testing.T) {
	ctx, cancel := context.WithCancel(context.Background())
	defer cancel()
	coord := coordinatortest.Serve(t, coordinator.Config{Logger: slog.New(slog.DiscardHandler),
		ClientTokens: []string{"c-token"}, WorkerTokens: []string{"w-token"}})

	dashCtx, stopDash := context.WithCancel(ctx)
	var stdout, stderr farmtest.SyncBuffer
	e := &env{stdout: &stdout, stderr: &stderr, getenv: func(string) string { return "" }}
	done := make(chan int, 1)
	go func() {
		done <- run(dashCtx, []string{"dashboard", "--coordinator", coord.Addr, "--listen", "127.0.0.1:0"}, e)
	}()
	var url string
	deadline := time.Now().Add(10 * time.Second)
	for {
		if line, _, ok := strings.Cut(stdout.String(), "\n"); ok {
			url = strings.TrimPrefix(line, "dashboard on ")
			if url == line || !strings.HasPrefix(url, "http://127.0.0.1:") || !strings.HasSuffix(url, "/") {
				t.Fatalf("first line %q, want \"dashboard on http://127.0.0.1:PORT/\"", line)
			}
			break
		}
		if time.Now().After(deadline) {
			t.Fatalf("no address line within 10s; stderr %q", stderr.String())
		}
		time.Sleep(10 * time.Millisecond)
	}
	resp, err := http.Get(url + "api/session")
	if err != nil {
		t.Fatal(err)
	}
	body, _ := io.ReadAll(resp.Body)
	resp.Body.Close()
	if resp.StatusCode != 200 || !strings.Contains(string(body), `"authRequired":true`) {
		t.Errorf("GET /api/session: %d %s", resp.StatusCode, body)
	}
	// An open event stream does not hold up the stop.
	req, _ := http.NewRequest("GET", url+"api/events", nil)
	req.Header.Set("Authorization", "Bearer c-token")
	stream, err := http.DefaultClient.Do(req)
	if err != nil || stream.StatusCode != 200 {
		t.Fatalf("GET /api/events: %v, %v", stream, err)
	}
	defer stream.Body.Close()
	stopDash()
	select {
	case code := <-done:
		if code != 0 {
			t.Errorf("farm dashboard exit %d, stderr %q", code, stderr.String())
		}
	case <-time.After(dashboardStopTimeout + 5*time.Second):
		t.Fatal("farm dashboard did not stop")
	}
}

func TestDashboardVerbRefusesPlaintextToAnotherMachine(t *testing.T) {
	code, _, stderr := runForTest(t, nil, "dashboard", "--coordinator", "192.0.2.1:7070", "--listen", "127.0.0.1:0")
	if code != exitUsage || !strings.Contains(stderr, "--tls-ca") {
		t.Errorf("exit %d, stderr %q; want a usage error naming --tls-ca", code, stderr)
	}
}
