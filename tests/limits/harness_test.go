package limits

import (
	"context"
	"flag"
	"fmt"
	"os"
	"regexp"
	"strconv"
	"strings"
	"testing"
	"time"

	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

var full = flag.Bool("limits.full", false, "run every job at the limit itself (minutes each, gigabytes of memory), not reduced")

// size is the full value when -limits.full is set, else the reduced one.
func size[T any](fullValue, reduced T) T {
	if *full {
		return fullValue
	}
	return reduced
}

// run is one job on a farm of its own: a coordinator and its workers.
type run struct {
	t       *testing.T
	f       *farmtest.Farm
	workers []*farmtest.Proc
	start   time.Time
}

// newRun starts a farm with one worker of two threads.
func newRun(t *testing.T) *run { return newRunOf(t, []string{"--threads", "2"}) }

// newRunOf starts a farm with a worker for each list of flags, each with a cache of its
// own.
func newRunOf(t *testing.T, workers ...[]string) *run {
	t.Helper()
	r := &run{t: t, f: farmtest.StartFarm(t, []string{"--lease-duration", "30s"})}
	for _, flags := range workers {
		r.workers = append(r.workers, r.f.StartWorker(t, flags...))
	}
	return r
}

// worker is the run's first worker.
func (r *run) worker() *farmtest.Proc { return r.workers[0] }

// render submits sc, waits up to timeout for it to succeed and logs the figures: the job's
// time and each phase's (from the job's events: a phase ends when its last task
// succeeds), and the peak resident memory of every process.
func (r *run) render(sc *pb.Scene, timeout time.Duration) *pb.Job {
	r.t.Helper()
	r.start = time.Now()
	submitted := r.f.Submit(r.t, sc)
	ended := map[pb.Phase]time.Time{}
	var order []pb.Phase
	job := r.f.WaitWatching(r.t, submitted.GetId(), timeout, func(ev *pb.WatchJobResponse) {
		for _, p := range ev.GetJob().GetPhases() {
			if _, seen := ended[p.GetPhase()]; !seen && p.GetTasksTotal() > 0 && p.GetTasksSucceeded() == p.GetTasksTotal() {
				ended[p.GetPhase()] = time.Now()
				order = append(order, p.GetPhase())
			}
		}
	})
	r.t.Logf("job %s: %.1f s", job.GetId(), time.Since(r.start).Seconds())
	last := r.start
	for _, p := range order {
		r.t.Logf("  phase %-18s %7.1f s (done at %.1f s)", strings.TrimPrefix(p.String(), "PHASE_"), ended[p].Sub(last).Seconds(), ended[p].Sub(r.start).Seconds())
		last = ended[p]
	}
	r.t.Logf("  peak RSS: coordinator %s", mb(r.f.Coordinator().PeakRSS(r.t)))
	for _, w := range r.workers {
		r.t.Logf("  peak RSS: %s %s", w.Name, mb(w.PeakRSS(r.t)))
	}
	return job
}

// taskTimes logs, per kind of task, how many ran and their summed and longest seconds,
// from the worker's log ("task done ... spec=\"render_tile (...)\" seconds=0.006") and the
// coordinator's ("photon map built ... phase=PHASE_BUILD ... took=1.2s").
func (r *run) taskTimes() {
	r.t.Helper()
	type sum struct {
		n          int
		total, max float64
	}
	sums := map[string]*sum{}
	var kinds []string
	add := func(kind string, seconds float64) {
		s := sums[kind]
		if s == nil {
			s = &sum{}
			sums[kind] = s
			kinds = append(kinds, kind)
		}
		s.n++
		s.total += seconds
		s.max = max(s.max, seconds)
	}
	worker := regexp.MustCompile(`msg="task done" .*spec="(\w+) .* seconds=([0-9.]+)`)
	builder := regexp.MustCompile(`msg="photon map built" .*phase=(\w+) .* took=(\S+)`)
	type log struct {
		path string
		re   *regexp.Regexp
	}
	logs := []log{{r.f.Coordinator().LogPath, builder}}
	for _, w := range r.workers {
		logs = append(logs, log{w.LogPath, worker})
	}
	for _, log := range logs {
		data, err := os.ReadFile(log.path)
		if err != nil {
			r.t.Fatal(err)
		}
		for _, m := range log.re.FindAllStringSubmatch(string(data), -1) {
			if d, err := time.ParseDuration(m[2]); err == nil {
				add(m[1], d.Seconds())
			} else if v, err := strconv.ParseFloat(m[2], 64); err == nil {
				add(m[1], v)
			}
		}
	}
	for _, k := range kinds {
		s := sums[k]
		r.t.Logf("  %-24s %6d tasks, %8.1f s in all, longest %.1f s", k, s.n, s.total, s.max)
	}
}

func mb(b uint64) string { return fmt.Sprintf("%.0f MB", float64(b)/1e6) }

func ctx(t *testing.T, d time.Duration) context.Context {
	c, cancel := context.WithTimeout(context.Background(), d)
	t.Cleanup(cancel)
	return c
}
