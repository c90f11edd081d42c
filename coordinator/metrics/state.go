package metrics

import (
	"context"

	"github.com/prometheus/client_golang/prometheus"

	"photonfarm/contract/tasks"
	pb "photonfarm/proto/renderfarm/v1"
)

var (
	jobsDesc = prometheus.NewDesc("farm_jobs", "Jobs by state.", []string{"state"}, nil)
	// Tasks of jobs that have not ended; the tasks of ended jobs are history.
	tasksDesc = prometheus.NewDesc("farm_tasks", "Tasks of unfinished jobs by state (queued, leased, ...).", []string{"state"}, nil)
	upDesc    = prometheus.NewDesc("farm_state_scrape_ok", "1 if the store answered the last count, else 0.", nil, nil)
)

// stateCollector reads the gauges from the store at scrape time, so they are never stale
// and cost nothing between scrapes.
type stateCollector struct {
	count CountFunc
}

func (c *stateCollector) Describe(ch chan<- *prometheus.Desc) {
	ch <- jobsDesc
	ch <- tasksDesc
	ch <- upDesc
}

func (c *stateCollector) Collect(ch chan<- prometheus.Metric) {
	ctx, cancel := context.WithTimeout(context.Background(), ScrapeTimeout)
	defer cancel()
	counts, err := c.count(ctx)
	if err != nil {
		ch <- prometheus.MustNewConstMetric(upDesc, prometheus.GaugeValue, 0)
		return
	}
	ch <- prometheus.MustNewConstMetric(upDesc, prometheus.GaugeValue, 1)
	// Every state is exported, zero or not, so that a series does not vanish when its
	// count drops to zero.
	for v := range pb.JobState_name {
		s := pb.JobState(v)
		if s == pb.JobState_JOB_STATE_UNSPECIFIED {
			continue
		}
		ch <- prometheus.MustNewConstMetric(jobsDesc, prometheus.GaugeValue, float64(counts.Jobs[s]), tasks.JobStateName(s))
	}
	for v := range pb.TaskState_name {
		s := pb.TaskState(v)
		if s == pb.TaskState_TASK_STATE_UNSPECIFIED {
			continue
		}
		ch <- prometheus.MustNewConstMetric(tasksDesc, prometheus.GaugeValue, float64(counts.Tasks[s]), tasks.TaskStateName(s))
	}
}
