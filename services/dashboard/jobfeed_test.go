package dashboard_test

import (
	"context"
	"log/slog"
	"net/http/httptest"
	"sync"
	"testing"
	"time"

	"google.golang.org/grpc"

	"photonfarm/contract/scene/scenetest"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/services/dashboard"
)

// countingConn counts the unary calls made through it, by method.
type countingConn struct {
	grpc.ClientConnInterface
	mu    sync.Mutex
	calls map[string]int
}

func (c *countingConn) Invoke(ctx context.Context, method string, args, reply any, opts ...grpc.CallOption) error {
	c.mu.Lock()
	c.calls[method]++
	c.mu.Unlock()
	return c.ClientConnInterface.Invoke(ctx, method, args, reply, opts...)
}

func (c *countingConn) count(method string) int {
	c.mu.Lock()
	defer c.mu.Unlock()
	return c.calls[method]
}

// TestTabsShareOneJobListPoll opens 8 job-list streams of one token (8 tabs) for a
// second, with the list read every 100 ms: the coordinator must see about 10 ListJobs
// calls, not 80, and a change of one job among 20 must reach each tab as that job alone.
func TestTabsShareOneJobListPoll(t *testing.T) {
	const tabs, poll, watch = 8, 100 * time.Millisecond, time.Second
	f := newFarm(t)
	var first *pb.Job
	for i := range 20 {
		job, err := f.c.Submit(f.ctx, scenetest.Unlit(16, 16))
		must(t, err)
		if i == 0 {
			first = job
		}
	}
	cc := &countingConn{ClientConnInterface: f.conn, calls: map[string]int{}}
	srv := httptest.NewServer(dashboard.New(dashboard.Config{Conn: cc, JobsPoll: poll, WorkersEvery: time.Hour,
		Logger: slog.New(slog.DiscardHandler)}))
	t.Cleanup(func() {
		srv.CloseClientConnections()
		srv.Close()
	})
	g := *f
	g.url = srv.URL
	b := g.browser(clientToken)
	var streams []*stream
	var listBytes int
	for range tabs {
		s := g.openStream(b, "/api/events")
		ev := s.until("the job list", func(ev event) bool { return ev.name == "jobs" })
		listBytes = len(ev.data)
		streams = append(streams, s)
	}

	before := cc.count(pb.JobService_ListJobs_FullMethodName)
	time.Sleep(watch)
	calls := cc.count(pb.JobService_ListJobs_FullMethodName) - before
	t.Logf("%d tabs for %v, the list read every %v: %d ListJobs calls (one poll per tab would be about %d)",
		tabs, watch, poll, calls, tabs*int(watch/poll))
	if most := 2 * int(watch/poll); calls > most {
		t.Errorf("%d ListJobs calls in %v; want at most %d: the tabs of one token share one poll", calls, watch, most)
	}

	_, err := f.c.Cancel(f.ctx, first.GetId())
	must(t, err)
	for i, s := range streams {
		ev := s.until("the change", func(ev event) bool { return ev.name == "jobs-changed" })
		var jobs []*pb.Job
		decode(t, ev.data, map[string]any{"jobs": &jobs})
		if len(jobs) != 1 || jobs[0].GetId() != first.GetId() || jobs[0].GetState() != pb.JobState_JOB_STATE_CANCELLED {
			t.Fatalf("tab %d: jobs-changed %v, want %s cancelled alone", i, jobs, first.GetId())
		}
		if i == 0 {
			t.Logf("a change of 1 job among 20 is sent as %d bytes; the whole list is %d", len(ev.data), listBytes)
		}
	}
}
