package dashboard_test

import (
	"bufio"
	"context"
	"encoding/json"
	"io"
	"log/slog"
	"net/http"
	"net/http/cookiejar"
	"net/http/httptest"
	"strings"
	"testing"
	"time"

	"google.golang.org/grpc"
	"google.golang.org/protobuf/encoding/protojson"

	"photonfarm/client"
	"photonfarm/coordinator"
	"photonfarm/coordinator/coordinatortest"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/services/dashboard"
)

const (
	clientToken = "client-secret-token"
	workerToken = "worker-secret-token"
)

// farm is a real coordinator on a loopback port with tokens, the dashboard in front of
// it, and gRPC clients of the coordinator for setting things up.
type farm struct {
	t       *testing.T
	ctx     context.Context
	url     string // the dashboard's, without a trailing slash
	http    *http.Client
	c       *client.Client         // with the client token
	workers pb.WorkerServiceClient // call with f.worker(ctx)
	conn    *grpc.ClientConn       // without a token
}

type farmOption func(*coordinator.Config, *dashboard.Config)

func noAuth() farmOption {
	return func(c *coordinator.Config, _ *dashboard.Config) { c.ClientTokens, c.WorkerTokens = nil, nil }
}

// dataDir runs the coordinator on dir, for tests that reach into its blob store.
func dataDir(dir string) farmOption {
	return func(c *coordinator.Config, _ *dashboard.Config) { c.DataDir = dir }
}

func newFarm(t *testing.T, opts ...farmOption) *farm {
	t.Helper()
	ctx, cancel := context.WithTimeout(context.Background(), 2*time.Minute)
	quiet := slog.New(slog.DiscardHandler)
	cc := coordinator.Config{LeaseDuration: time.Minute, Logger: quiet,
		ClientTokens: []string{clientToken}, WorkerTokens: []string{workerToken}}
	dc := dashboard.Config{Logger: quiet, JobsPoll: 50 * time.Millisecond, WorkersEvery: 200 * time.Millisecond, JobUpdateEvery: 20 * time.Millisecond,
		RefusedTokenBurst: 1000} // the tests present many wrong tokens; throttle_test.go tests the default
	for _, o := range opts {
		o(&cc, &dc)
	}
	coord := coordinatortest.Serve(t, cc)
	t.Cleanup(cancel)
	conn := coord.Dial(t, dashboard.DialOptions()...)
	dc.Conn = conn
	srv := httptest.NewServer(dashboard.New(dc))
	c, err := client.Dial(coord.Addr, client.WithToken(clientToken))
	if err != nil {
		t.Fatal(err)
	}
	t.Cleanup(func() {
		srv.CloseClientConnections()
		srv.Close()
		c.Close()
	})
	workers := pb.NewWorkerServiceClient(coord.Dial(t, client.WorkerSecrets()))
	return &farm{t: t, ctx: ctx, url: srv.URL, http: srv.Client(), c: c, workers: workers, conn: conn}
}

// worker returns ctx with the worker token.
func (f *farm) worker() context.Context {
	return client.ContextWithToken(f.ctx, workerToken)
}

// browser returns an HTTP client with a cookie jar, logged in with token unless it is "".
func (f *farm) browser(token string) *http.Client {
	f.t.Helper()
	jar, _ := cookiejar.New(nil)
	b := &http.Client{Jar: jar, Timeout: time.Minute}
	if token != "" {
		resp := f.do(b, "POST", "/api/login", `{"token": "`+token+`"}`)
		if resp.StatusCode != http.StatusOK {
			f.t.Fatalf("login: %d %s", resp.StatusCode, resp.Body)
		}
	}
	return b
}

// response is an answer with its body read.
type response struct {
	StatusCode int
	Header     http.Header
	Body       string
	Cookies    []*http.Cookie
}

func (f *farm) do(b *http.Client, method, path, body string) response {
	f.t.Helper()
	req, err := http.NewRequestWithContext(f.ctx, method, f.url+path, strings.NewReader(body))
	if err != nil {
		f.t.Fatal(err)
	}
	if method == http.MethodPost {
		req.Header.Set("Content-Type", "application/json") // as the front end sends
	}
	resp, err := b.Do(req)
	if err != nil {
		f.t.Fatalf("%s %s: %v", method, path, err)
	}
	defer resp.Body.Close()
	data, err := io.ReadAll(resp.Body)
	if err != nil {
		f.t.Fatalf("%s %s: %v", method, path, err)
	}
	return response{StatusCode: resp.StatusCode, Header: resp.Header, Body: string(data), Cookies: resp.Cookies()}
}

// wantStatus checks the status and, for errors, the {"error": ...} body.
func wantStatus(t *testing.T, what string, r response, code int) {
	t.Helper()
	if r.StatusCode != code {
		t.Fatalf("%s: status %d (%s), want %d", what, r.StatusCode, r.Body, code)
	}
	if code >= 400 {
		var e struct{ Error string }
		if err := json.Unmarshal([]byte(r.Body), &e); err != nil || e.Error == "" {
			t.Errorf("%s: body %q, want {\"error\": \"...\"}", what, r.Body)
		}
	}
}

// decode decodes a JSON answer whose fields are protobuf messages (protojson) or lists
// of them into out's fields, by JSON name.
func decode(t *testing.T, body string, out map[string]any) {
	t.Helper()
	var raw map[string]json.RawMessage
	if err := json.Unmarshal([]byte(body), &raw); err != nil {
		t.Fatalf("answer %q: %v", body, err)
	}
	for name, dst := range out {
		data, ok := raw[name]
		if !ok {
			t.Fatalf("answer %.300q has no %q", body, name)
		}
		unmarshalInto(t, data, dst)
	}
}

func unmarshalInto(t *testing.T, data json.RawMessage, dst any) {
	t.Helper()
	switch d := dst.(type) {
	case *pb.Job:
		must(t, protojson.Unmarshal(data, d))
	case *pb.Task:
		must(t, protojson.Unmarshal(data, d))
	case *[]*pb.Job:
		*d = listOf(t, data, func() *pb.Job { return &pb.Job{} })
	case *[]*pb.Task:
		*d = listOf(t, data, func() *pb.Task { return &pb.Task{} })
	case *[]*pb.WorkerInfo:
		*d = listOf(t, data, func() *pb.WorkerInfo { return &pb.WorkerInfo{} })
	default:
		must(t, json.Unmarshal(data, d))
	}
}

func listOf[M interface {
	*pb.Job | *pb.Task | *pb.WorkerInfo
}](t *testing.T, data json.RawMessage, mk func() M) []M {
	t.Helper()
	var items []json.RawMessage
	must(t, json.Unmarshal(data, &items))
	if items == nil {
		t.Fatalf("list %s is not a JSON array", data)
	}
	out := make([]M, len(items))
	for i, it := range items {
		m := mk()
		switch v := any(m).(type) {
		case *pb.Job:
			must(t, protojson.Unmarshal(it, v))
		case *pb.Task:
			must(t, protojson.Unmarshal(it, v))
		case *pb.WorkerInfo:
			must(t, protojson.Unmarshal(it, v))
		}
		out[i] = m
	}
	return out
}

func must(t *testing.T, err error) {
	t.Helper()
	if err != nil {
		t.Fatal(err)
	}
}

// event is one server-sent event.
type event struct {
	name, data string
}

// stream is an open event stream.
type stream struct {
	t      *testing.T
	events chan event
	cancel context.CancelFunc
	resp   *http.Response
}

// openStream GETs an event stream with b and reads its events in the background.
func (f *farm) openStream(b *http.Client, path string) *stream {
	f.t.Helper()
	ctx, cancel := context.WithCancel(f.ctx)
	req, _ := http.NewRequestWithContext(ctx, "GET", f.url+path, nil)
	resp, err := b.Do(req)
	if err != nil {
		cancel()
		f.t.Fatalf("GET %s: %v", path, err)
	}
	s := &stream{t: f.t, events: make(chan event, 1000), cancel: cancel, resp: resp}
	f.t.Cleanup(func() { cancel(); resp.Body.Close() })
	if resp.StatusCode != http.StatusOK {
		return s
	}
	go func() {
		defer close(s.events)
		sc := bufio.NewScanner(resp.Body)
		sc.Buffer(nil, 64<<20)
		var ev event
		for sc.Scan() {
			line := sc.Text()
			switch {
			case line == "":
				if ev.name != "" || ev.data != "" {
					s.events <- ev
				}
				ev = event{}
			case strings.HasPrefix(line, "event: "):
				ev.name = strings.TrimPrefix(line, "event: ")
			case strings.HasPrefix(line, "data: "):
				ev.data += strings.TrimPrefix(line, "data: ")
			}
		}
	}()
	return s
}

// next returns the next event, failing after 30 s or at the end of the stream.
func (s *stream) next() event {
	s.t.Helper()
	select {
	case ev, ok := <-s.events:
		if !ok {
			s.t.Fatal("the event stream ended")
		}
		return ev
	case <-time.After(30 * time.Second):
		s.t.Fatal("no event within 30s")
	}
	return event{}
}

// until returns the first event for which ok holds, skipping others.
func (s *stream) until(what string, ok func(event) bool) event {
	s.t.Helper()
	deadline := time.After(30 * time.Second)
	for {
		select {
		case ev, open := <-s.events:
			if !open {
				s.t.Fatalf("the event stream ended before %s", what)
			}
			if ok(ev) {
				return ev
			}
		case <-deadline:
			s.t.Fatalf("no %s within 30s", what)
		}
	}
}

// ended reports whether the stream closes (within 10 s) with no further event.
func (s *stream) ended() bool {
	select {
	case ev, ok := <-s.events:
		if ok {
			s.t.Errorf("event %s after the end: %.200s", ev.name, ev.data)
		}
		return !ok
	case <-time.After(10 * time.Second):
		return false
	}
}
