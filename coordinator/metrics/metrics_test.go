package metrics_test

import (
	"context"
	"errors"
	"io"
	"net"
	"net/http/httptest"
	"strings"
	"testing"

	"google.golang.org/grpc"
	"google.golang.org/grpc/credentials/insecure"
	"google.golang.org/grpc/health"
	healthpb "google.golang.org/grpc/health/grpc_health_v1"

	"photonfarm/coordinator/metrics"
	"photonfarm/coordinator/store"
	"photonfarm/coordinator/store/memstore"
	pb "photonfarm/proto/renderfarm/v1"
)

// scrape returns the exposition text of m.
func scrape(t *testing.T, m *metrics.Metrics) string {
	t.Helper()
	rec := httptest.NewRecorder()
	m.Handler().ServeHTTP(rec, httptest.NewRequest("GET", "/metrics", nil))
	if rec.Code != 200 {
		t.Fatalf("GET /metrics = %d", rec.Code)
	}
	body, _ := io.ReadAll(rec.Body)
	return string(body)
}

// wantLines fails unless every line is in the exposition text.
func wantLines(t *testing.T, text string, lines ...string) {
	t.Helper()
	for _, l := range lines {
		if !strings.Contains(text, "\n"+l+"\n") {
			t.Errorf("metrics lack %q", l)
		}
	}
}

func renderTasks(n int) []*pb.Task {
	var tasks []*pb.Task
	for i := range n {
		tasks = append(tasks, &pb.Task{Index: uint32(i), Phase: pb.Phase_PHASE_RENDER,
			Spec: &pb.Task_RenderTile{RenderTile: &pb.RenderTileSpec{}}})
	}
	return tasks
}

func TestGaugesCountJobsAndTasksFromTheStore(t *testing.T) {
	ctx := context.Background()
	st := memstore.New(store.Options{})
	// Ahead of the other job, so that it gets both leases.
	running, err := st.CreateJob(ctx, store.NewJob{SceneDigest: "sha256:a", Tasks: renderTasks(5), Priority: 1})
	if err != nil {
		t.Fatal(err)
	}
	if _, err := st.CreateJob(ctx, store.NewJob{SceneDigest: "sha256:b", Tasks: renderTasks(3)}); err != nil {
		t.Fatal(err)
	}
	cancelled, _ := st.CreateJob(ctx, store.NewJob{SceneDigest: "sha256:c", Tasks: renderTasks(2)})
	if _, err := st.CancelJob(ctx, cancelled.GetId()); err != nil {
		t.Fatal(err)
	}
	for range 2 {
		l, err := st.LeaseTask(ctx, "w-1", store.WorkerPhases)
		if err != nil || l == nil || l.Task.GetJobId() != running.GetId() {
			t.Fatalf("lease = %v, %v", l, err)
		}
	}
	m := metrics.New(metrics.StoreCounts(st))
	wantLines(t, scrape(t, m),
		`farm_jobs{state="running"} 1`, `farm_jobs{state="queued"} 1`, `farm_jobs{state="cancelled"} 1`,
		`farm_jobs{state="succeeded"} 0`,
		// The cancelled job's tasks are not counted: only unfinished jobs' are.
		`farm_tasks{state="leased"} 2`, `farm_tasks{state="queued"} 6`, `farm_tasks{state="cancelled"} 0`,
		`farm_state_scrape_ok 1`)
}

func TestAFailingCountIsReportedNotFatal(t *testing.T) {
	m := metrics.New(func(context.Context) (metrics.Counts, error) { return metrics.Counts{}, errors.New("redis down") })
	text := scrape(t, m)
	wantLines(t, text, "farm_state_scrape_ok 0")
	if strings.Contains(text, "farm_jobs{") {
		t.Error("job gauges exported without counts")
	}
}

func TestCountersCountWhatTheyAreTold(t *testing.T) {
	m := metrics.New(nil)
	m.LeaseGranted(pb.Phase_PHASE_RENDER)
	m.LeaseGranted(pb.Phase_PHASE_RENDER)
	m.LeaseGranted(pb.Phase_PHASE_EMIT)
	m.LeaseExpired()
	m.TaskFailed()
	m.TaskCompleted(pb.Phase_PHASE_COMPOSITE)
	m.JobSubmitted()
	m.TileSamplesRendered(&pb.TileSamples{Samples: 1024, Nonfinite: 2, Zero: 5})
	m.TileSamplesRendered(&pb.TileSamples{Samples: 1024, Zero: 1})
	m.TileSamplesRendered(nil) // a task that is not a render tile
	wantLines(t, scrape(t, m),
		`farm_leases_granted_total{phase="render"} 2`, `farm_leases_granted_total{phase="emit"} 1`,
		"farm_lease_expiries_total 1", "farm_task_failures_total 1",
		`farm_tasks_completed_total{phase="composite"} 1`, "farm_jobs_submitted_total 1",
		`farm_render_samples_total{outcome="all"} 2048`, `farm_render_samples_total{outcome="nonfinite"} 2`,
		`farm_render_samples_total{outcome="zero"} 6`)
}

func TestInterceptorTimesRealRPCsByMethodAndCode(t *testing.T) {
	m := metrics.New(nil)
	srv := grpc.NewServer(grpc.ChainUnaryInterceptor(m.UnaryServerInterceptor), grpc.ChainStreamInterceptor(m.StreamServerInterceptor))
	hs := health.NewServer()
	healthpb.RegisterHealthServer(srv, hs)
	lis, err := net.Listen("tcp", "127.0.0.1:0")
	if err != nil {
		t.Fatal(err)
	}
	go func() { _ = srv.Serve(lis) }()
	t.Cleanup(srv.Stop)
	conn, err := grpc.NewClient(lis.Addr().String(), grpc.WithTransportCredentials(insecure.NewCredentials()))
	if err != nil {
		t.Fatal(err)
	}
	defer conn.Close()
	hc := healthpb.NewHealthClient(conn)
	ctx := context.Background()
	for range 3 {
		if _, err := hc.Check(ctx, &healthpb.HealthCheckRequest{}); err != nil {
			t.Fatal(err)
		}
	}
	if _, err := hc.Check(ctx, &healthpb.HealthCheckRequest{Service: "no-such-service"}); err == nil {
		t.Fatal("Check of an unknown service succeeded")
	}
	wantLines(t, scrape(t, m),
		`farm_rpc_duration_seconds_count{code="OK",method="/grpc.health.v1.Health/Check"} 3`,
		`farm_rpc_duration_seconds_count{code="NotFound",method="/grpc.health.v1.Health/Check"} 1`)
}

func TestNilMetricsCountNothingAndDoNotPanic(t *testing.T) {
	var m *metrics.Metrics
	m.LeaseGranted(pb.Phase_PHASE_RENDER)
	m.LeaseExpired()
	m.TaskFailed()
	m.TaskCompleted(pb.Phase_PHASE_RENDER)
	m.JobSubmitted()
	m.TileSamplesRendered(&pb.TileSamples{Samples: 1})
}
