package stiff

// The suite's small harness: one real farm (a `farm coordinator` process and two
// `farm-worker` processes, started with tests/farmtest) shared by every case of
// TestStiffAndExtremeCases, a render helper that submits a scene, downloads the final EXR
// and counts the camera samples that came out NaN or infinite (from the coordinator's
// metrics), and a reader for that EXR built on `oiiotool` (see exr_test.go). The cases
// share one farm, where tests/integration starts one per test, so that each case costs
// about a second.

import (
	"context"
	"flag"
	"fmt"
	"io"
	"net/http"
	"os"
	"path/filepath"
	"regexp"
	"strconv"
	"strings"
	"sync"
	"testing"
	"time"

	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

// heavy turns on the cases too slow for the test command on two cores (10 million photons).
var heavy = flag.Bool("stiff.heavy", false, "also run the heavy stiff cases (10,000,000 photon paths)")

// suiteWorkers is the number of farm-worker processes the shared farm runs.
const suiteWorkers = 2

// farm is the suite's shared farm: the coordinator, its client and the workers.
type farm struct {
	*farmtest.Farm
	suite   *testing.T // the test the farm belongs to, which outlives every case
	cache   string     // the cache folder the workers share
	metrics string     // the coordinator's metrics URL

	mu      sync.Mutex
	workers []*farmtest.Proc
}

// startSuiteFarm starts the shared farm for the suite test t: a coordinator with leases of
// 5 s (a case's tasks take up to a few seconds on a loaded machine) serving its metrics,
// and suiteWorkers workers with one render thread each (two workers on two cores) and one
// cache folder, as workers on one host share it by default. Everything stops when t ends.
func startSuiteFarm(t *testing.T) *farm {
	t.Helper()
	f := &farm{Farm: farmtest.StartFarm(t, []string{"--lease-duration", "5s", "--metrics-listen", "127.0.0.1:0"}),
		suite: t, cache: filepath.Join(t.TempDir(), "cache")}
	f.metrics = metricsURL(t, f.Coordinator())
	for range suiteWorkers {
		f.workers = append(f.workers, f.StartWorkerWithCache(t, f.cache))
	}
	return f
}

// reviveWorkers restarts any worker that has died (a crash in an earlier case must not
// take the later cases down with it) and returns the names of those it restarted. The new
// workers belong to the suite test, not to the case that asked, so that they outlive it.
func (f *farm) reviveWorkers() []string {
	return f.eachExited(func(i int, w *farmtest.Proc) string {
		f.workers[i] = f.StartWorkerWithCache(f.suite, f.cache)
		return fmt.Sprintf("%s (exited: %v)", w.Name, w.Err())
	})
}

// deadWorkers lists the workers that have exited, with their log tails.
func (f *farm) deadWorkers() []string {
	return f.eachExited(func(_ int, w *farmtest.Proc) string {
		return fmt.Sprintf("%s exited: %v\n--- %s log ---\n%s", w.Name, w.Err(), w.Name, w.LogTail(30))
	})
}

// eachExited calls fn, holding the workers' lock, with each worker that has exited and
// its index, and returns what fn says of them.
func (f *farm) eachExited(fn func(i int, w *farmtest.Proc) string) []string {
	f.mu.Lock()
	defer f.mu.Unlock()
	var out []string
	for i, w := range f.workers {
		if w.Exited() {
			out = append(out, fn(i, w))
		}
	}
	return out
}

var metricsLine = regexp.MustCompile(`metrics on (http://\S+/metrics)`)

// metricsURL waits up to 15 s for coordinator p to say where it serves its metrics.
func metricsURL(t *testing.T, p *farmtest.Proc) string {
	t.Helper()
	for deadline := time.Now().Add(15 * time.Second); time.Now().Before(deadline); time.Sleep(50 * time.Millisecond) {
		if m := metricsLine.FindStringSubmatch(p.LogTail(1000)); m != nil {
			return m[1]
		}
	}
	t.Fatalf("%s did not say where it serves its metrics", p.Name)
	return ""
}

// nonfiniteSamples is the coordinator's count of camera samples with a light term that
// came out NaN or infinite, farm_render_samples_total{outcome="nonfinite"}, over every
// render tile completed so far. The worker drops such a sample from its pixel (so the EXR
// stays finite) and counts it: a renderer bug the EXR alone would hide.
func (f *farm) nonfiniteSamples(t *testing.T) uint64 {
	t.Helper()
	resp, err := http.Get(f.metrics)
	if err != nil {
		t.Fatalf("coordinator metrics: %v", err)
	}
	defer resp.Body.Close()
	body, err := io.ReadAll(resp.Body)
	if err != nil {
		t.Fatalf("coordinator metrics: %v", err)
	}
	const series = `farm_render_samples_total{outcome="nonfinite"} `
	for _, line := range strings.Split(string(body), "\n") {
		if rest, ok := strings.CutPrefix(line, series); ok {
			n, err := strconv.ParseFloat(rest, 64)
			if err != nil {
				t.Fatalf("coordinator metrics: line %q: %v", line, err)
			}
			return uint64(n)
		}
	}
	return 0 // no tile has reported samples yet
}

// rendered is the result of one case's render.
type rendered struct {
	job     *pb.Job
	img     *image
	elapsed time.Duration // from submit until the job ended
}

// render submits sc, waits up to timeout for the job to end, downloads the final EXR and
// reads it. It fails t (naming the case) if the job does not succeed, if a worker dies
// while it runs, if the EXR cannot be read, or if any camera sample of the job came out
// NaN or infinite (the cases and references render one at a time, so the coordinator's
// count grows only with this job's tiles while it runs).
func (f *farm) render(t *testing.T, name string, sc *pb.Scene, timeout time.Duration) *rendered {
	t.Helper()
	if revived := f.reviveWorkers(); len(revived) > 0 {
		t.Logf("case %s: restarted workers left dead by an earlier case: %s", name, strings.Join(revived, "; "))
	}
	if sc.Name == "" {
		sc.Name = "stiff-" + name
	}
	nonfiniteBefore := f.nonfiniteSamples(t)
	start := time.Now()
	ctx, cancel := context.WithTimeout(context.Background(), timeout)
	defer cancel()
	job, err := f.Client.Submit(ctx, sc)
	if err != nil {
		t.Fatalf("case %s: submit: %v", name, err)
	}
	ended, err := f.Client.Watch(ctx, job.GetId(), nil)
	elapsed := time.Since(start)
	if dead := f.deadWorkers(); len(dead) > 0 {
		t.Errorf("case %s: a worker died during the render (a crash):\n%s", name, strings.Join(dead, "\n"))
	}
	if err != nil {
		last, _ := f.Client.GetJob(context.Background(), job.GetId())
		f.cancel(job.GetId())
		t.Fatalf("case %s: job %s did not end within %s: %v (last seen: %v)\n%s",
			name, job.GetId(), timeout, err, last, f.logs())
	}
	if ended.GetState() != pb.JobState_JOB_STATE_SUCCEEDED {
		t.Fatalf("case %s: job %s ended %v: %s\n%s", name, job.GetId(), ended.GetState(), ended.GetError(), f.logs())
	}
	if n := f.nonfiniteSamples(t) - nonfiniteBefore; n > 0 {
		t.Errorf("case %s: %d camera samples came out NaN or infinite (dropped from their pixels by the worker, so the EXR does not show them; farm_render_samples_total{outcome=\"nonfinite\"})", name, n)
	}
	exr := f.Output(t, ended, "image.exr")
	path := filepath.Join(t.TempDir(), name+".exr")
	if err := os.WriteFile(path, exr, 0o644); err != nil {
		t.Fatal(err)
	}
	img, err := readEXR(path)
	if err != nil {
		t.Fatalf("case %s: %v", name, err)
	}
	if img.width != int(sc.GetFilm().GetWidth()) || img.height != int(sc.GetFilm().GetHeight()) {
		t.Fatalf("case %s: EXR is %dx%d, want %dx%d", name, img.width, img.height, sc.GetFilm().GetWidth(), sc.GetFilm().GetHeight())
	}
	if os.Getenv("STIFF_KEEP") != "" { // for looking at a case by hand
		keep := filepath.Join(os.Getenv("STIFF_KEEP"), name+".exr")
		os.MkdirAll(filepath.Dir(keep), 0o755)
		os.WriteFile(keep, exr, 0o644)
	}
	t.Logf("case %s: job %s took %s", name, job.GetId(), elapsed.Round(time.Millisecond))
	return &rendered{job: ended, img: img, elapsed: elapsed}
}

func (f *farm) cancel(jobID string) {
	ctx, cancel := context.WithTimeout(context.Background(), 5*time.Second)
	defer cancel()
	f.Client.Cancel(ctx, jobID)
}

// logs is the tail of every process's log, for a failure message.
func (f *farm) logs() string {
	f.mu.Lock()
	defer f.mu.Unlock()
	var b strings.Builder
	for _, p := range append([]*farmtest.Proc{f.Coordinator()}, f.workers...) {
		fmt.Fprintf(&b, "--- %s log ---\n%s\n", p.Name, p.LogTail(20))
	}
	return b.String()
}

// memo renders each reference scene once per run, however many cases compare with it.
type memo struct {
	mu   sync.Mutex
	done map[string]*rendered
}

var references = memo{done: map[string]*rendered{}}

// reference renders the named reference scene (built by mk) once and returns it.
func reference(t *testing.T, f *farm, name string, mk func() *pb.Scene) *rendered {
	t.Helper()
	references.mu.Lock()
	defer references.mu.Unlock()
	if r, ok := references.done[name]; ok {
		return r
	}
	r := f.render(t, "reference-"+name, mk(), 2*time.Minute)
	checkFinite(t, "reference-"+name, r.img)
	references.done[name] = r
	return r
}
