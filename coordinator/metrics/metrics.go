// Package metrics is the coordinator's Prometheus instrumentation: RPC latencies by method
// and status code, counters of what happens to tasks (leases granted and expired, failures
// retried, completions), and gauges of jobs and tasks by state, read from the store when
// Prometheus scrapes. Handler serves them in the text exposition format.
package metrics

import (
	"context"
	"net/http"
	"time"

	"github.com/prometheus/client_golang/prometheus"
	"github.com/prometheus/client_golang/prometheus/collectors"
	"github.com/prometheus/client_golang/prometheus/promhttp"

	"photonfarm/contract/tasks"
	pb "photonfarm/proto/renderfarm/v1"
)

// Counts is the farm's state at one moment.
type Counts struct {
	Jobs  map[pb.JobState]int
	Tasks map[pb.TaskState]int
}

// CountFunc reads Counts; a scrape calls it once, with a deadline.
type CountFunc func(ctx context.Context) (Counts, error)

// ScrapeTimeout bounds how long a scrape may spend counting.
const ScrapeTimeout = 5 * time.Second

// Metrics holds the coordinator's collectors in a registry of its own, so that two
// coordinators in one process (tests) do not collide.
type Metrics struct {
	reg           *prometheus.Registry
	rpcSeconds    *prometheus.HistogramVec
	rpcRefused    *prometheus.CounterVec
	leases        *prometheus.CounterVec
	leaseExpiries prometheus.Counter
	retries       prometheus.Counter
	completions   *prometheus.CounterVec
	jobsSubmitted prometheus.Counter
	samples       *prometheus.CounterVec
}

// New registers every collector; count feeds the jobs and tasks gauges (nil: none).
func New(count CountFunc) *Metrics {
	m := &Metrics{
		reg: prometheus.NewRegistry(),
		rpcSeconds: prometheus.NewHistogramVec(prometheus.HistogramOpts{
			Name:    "farm_rpc_duration_seconds",
			Help:    "Latency of the coordinator's gRPC calls, by method and status code (streams: until they end).",
			Buckets: prometheus.ExponentialBuckets(0.0005, 2.5, 14),
		}, []string{"method", "code"}),
		rpcRefused: prometheus.NewCounterVec(prometheus.CounterOpts{
			Name: "farm_rpc_refused_total",
			Help: "Calls refused by the token check before any of their message was read (not in farm_rpc_duration_seconds), by method (\"unknown\" for a name the farm does not serve) and status code.",
		}, []string{"method", "code"}),
		leases: prometheus.NewCounterVec(prometheus.CounterOpts{
			Name: "farm_leases_granted_total",
			Help: "Task leases granted, by phase.",
		}, []string{"phase"}),
		leaseExpiries: prometheus.NewCounter(prometheus.CounterOpts{
			Name: "farm_lease_expiries_total",
			Help: "Leases that expired without a report (a lost or stuck worker); the task is queued again.",
		}),
		retries: prometheus.NewCounter(prometheus.CounterOpts{
			Name: "farm_task_failures_total",
			Help: "Task failures reported by workers (each is retried until the attempt limit).",
		}),
		completions: prometheus.NewCounterVec(prometheus.CounterOpts{
			Name: "farm_tasks_completed_total",
			Help: "Tasks completed, by phase.",
		}, []string{"phase"}),
		jobsSubmitted: prometheus.NewCounter(prometheus.CounterOpts{
			Name: "farm_jobs_submitted_total",
			Help: "Jobs accepted by SubmitJob.",
		}),
		samples: prometheus.NewCounterVec(prometheus.CounterOpts{
			Name: "farm_render_samples_total",
			Help: "Camera samples of completed render tiles as their workers counted them (TileSamples), by outcome: \"all\"; \"nonfinite\", a light term NaN or infinite; \"zero\", exactly black although the path reached a non-specular surface. Either of the last two is a renderer bug where light reaches.",
		}, []string{"outcome"}),
	}
	m.reg.MustRegister(m.rpcSeconds, m.rpcRefused, m.leases, m.leaseExpiries, m.retries, m.completions, m.jobsSubmitted, m.samples,
		collectors.NewGoCollector(), collectors.NewProcessCollector(collectors.ProcessCollectorOpts{}))
	if count != nil {
		m.reg.MustRegister(&stateCollector{count: count})
	}
	return m
}

// Handler serves the metrics (GET /metrics).
func (m *Metrics) Handler() http.Handler {
	return promhttp.HandlerFor(m.reg, promhttp.HandlerOpts{ErrorHandling: promhttp.ContinueOnError})
}

// The counting methods do nothing on a nil *Metrics, so that a service without metrics
// (unit tests) needs no checks at the call sites.

// LeaseGranted counts a lease of a task of phase.
func (m *Metrics) LeaseGranted(phase pb.Phase) {
	if m != nil {
		m.leases.WithLabelValues(tasks.Name(phase)).Inc()
	}
}

// LeaseExpired counts a lease that expired.
func (m *Metrics) LeaseExpired() {
	if m != nil {
		m.leaseExpiries.Inc()
	}
}

// TaskFailed counts a failure a worker reported.
func (m *Metrics) TaskFailed() {
	if m != nil {
		m.retries.Inc()
	}
}

// TaskCompleted counts a completed task of phase.
func (m *Metrics) TaskCompleted(phase pb.Phase) {
	if m != nil {
		m.completions.WithLabelValues(tasks.Name(phase)).Inc()
	}
}

// TileSamplesRendered counts a completed render tile's camera samples (nil: none).
func (m *Metrics) TileSamplesRendered(s *pb.TileSamples) {
	if m != nil && s != nil {
		m.samples.WithLabelValues("all").Add(float64(s.GetSamples()))
		m.samples.WithLabelValues("nonfinite").Add(float64(s.GetNonfinite()))
		m.samples.WithLabelValues("zero").Add(float64(s.GetZero()))
	}
}

// JobSubmitted counts an accepted job.
func (m *Metrics) JobSubmitted() {
	if m != nil {
		m.jobsSubmitted.Inc()
	}
}
