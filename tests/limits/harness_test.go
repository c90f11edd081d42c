package limits

import (
	"context"
	"flag"
	"fmt"
	"os"
	"regexp"
	"strconv"
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

// run is one job on a farm of its own: a coordinator and one worker of two threads.
type run struct {
	t      *testing.T
	f      *farmtest.Farm
	worker *farmtest.Proc
	start  time.Time
}

func newRun(t *testing.T) *run {
	t.Helper()
	f := farmtest.StartFarm(t, []string{"--lease-duration", "30s"})
	return &run{t: t, f: f, worker: f.StartWorker(t, "--threads", "2")}
}

// render submits sc, waits up to timeout for it to succeed and logs the figures.
func (r *run) render(sc *pb.Scene, timeout time.Duration) *pb.Job {
	r.t.Helper()
	r.start = time.Now()
	job := r.f.Render(r.t, sc, timeout)
	r.t.Logf("job %s: %.1f s; peak RSS: coordinator %s, worker %s", job.GetId(), time.Since(r.start).Seconds(),
		mb(r.f.Coordinator().PeakRSS(r.t)), mb(r.worker.PeakRSS(r.t)))
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
	for _, log := range []struct {
		path string
		re   *regexp.Regexp
	}{{r.worker.LogPath, worker}, {r.f.Coordinator().LogPath, builder}} {
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
