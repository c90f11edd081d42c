package stiff

// The suite's small harness: one real farm (a `farm coordinator` process and two
// `farm-worker` processes from $FARM_BIN_DIR) started on first use and shared by every case,
// a render helper that submits a scene and downloads the final EXR, and a reader for that
// EXR built on `oiiotool` (see exr_test.go). Ideas come from tests/integration's harness
// (process groups, reading the coordinator's port from its log, failing rather than skipping
// without binaries); it is kept separate because those tests start a farm per test, while
// these share one so that each case costs about a second.

import (
	"bufio"
	"context"
	"flag"
	"fmt"
	"os"
	"os/exec"
	"path/filepath"
	"runtime"
	"strings"
	"sync"
	"syscall"
	"testing"
	"time"

	"photonfarm/client"
	pb "photonfarm/proto/renderfarm/v1"
)

// heavy turns on the cases too slow for the test command on two cores (10 million photons).
var heavy = flag.Bool("stiff.heavy", false, "also run the heavy stiff cases (10,000,000 photon paths)")

// suiteWorkers is the number of farm-worker processes the shared farm runs.
const suiteWorkers = 2

func TestMain(m *testing.M) {
	flag.Parse()
	code := m.Run()
	if shared != nil {
		shared.stop()
	}
	if scratch != "" {
		os.RemoveAll(scratch)
	}
	os.Exit(code)
}

var (
	sharedOnce sync.Once
	shared     *farm
	sharedErr  error
	scratch    string // the suite's temporary folder (data, caches, logs)
)

// binDir returns $FARM_BIN_DIR, where `farm` and `farm-worker` are built. The suite exists
// to run the real binaries: without them it fails rather than skips.
func binDir() (string, error) {
	dir := os.Getenv("FARM_BIN_DIR")
	if dir == "" {
		return "", fmt.Errorf("FARM_BIN_DIR is not set: the stiff suite runs the built binaries. " +
			"Build them (make build) and run FARM_BIN_DIR=$PWD/build/bin go test ./tests/stiff, or run make test")
	}
	for _, b := range []string{"farm", "farm-worker"} {
		if _, err := os.Stat(filepath.Join(dir, b)); err != nil {
			return "", fmt.Errorf("FARM_BIN_DIR=%s: %v (build with make build)", dir, err)
		}
	}
	return filepath.Abs(dir)
}

// repoRoot is the module root, two folders above this package.
func repoRoot() string {
	_, file, _, _ := runtime.Caller(0)
	return filepath.Dir(filepath.Dir(filepath.Dir(file)))
}

// proc is a process the suite started, in a process group of its own, logging to a file.
type proc struct {
	name    string
	cmd     *exec.Cmd
	logPath string
	done    chan struct{}
	err     error // exit status, once done is closed
}

func startProc(name, bin string, args []string, onLine func(string)) (*proc, error) {
	logPath := filepath.Join(scratch, name+".log")
	logf, err := os.OpenFile(logPath, os.O_CREATE|os.O_WRONLY|os.O_APPEND, 0o644)
	if err != nil {
		return nil, err
	}
	cmd := exec.Command(bin, args...)
	cmd.Stdout = logf
	// Pdeathsig: if the test binary dies (a panic, go test's -timeout) before TestMain can
	// stop the farm, the kernel kills it rather than leaving it running.
	cmd.SysProcAttr = &syscall.SysProcAttr{Setpgid: true, Pdeathsig: syscall.SIGKILL}
	pr, pw, err := os.Pipe()
	if err != nil {
		logf.Close()
		return nil, err
	}
	cmd.Stderr = pw
	if err := cmd.Start(); err != nil {
		logf.Close()
		pr.Close()
		pw.Close()
		return nil, fmt.Errorf("start %s: %v", name, err)
	}
	pw.Close()
	p := &proc{name: name, cmd: cmd, logPath: logPath, done: make(chan struct{})}
	var copying sync.WaitGroup
	copying.Add(1)
	go func() {
		defer copying.Done()
		sc := bufio.NewScanner(pr)
		sc.Buffer(make([]byte, 64*1024), 1024*1024)
		for sc.Scan() {
			fmt.Fprintln(logf, sc.Text())
			if onLine != nil {
				onLine(sc.Text())
			}
		}
		pr.Close()
	}()
	go func() {
		p.err = cmd.Wait()
		copying.Wait()
		logf.Close()
		close(p.done)
	}()
	return p, nil
}

func (p *proc) exited() bool {
	select {
	case <-p.done:
		return true
	default:
		return false
	}
}

// kill SIGKILLs the process's group and waits for it.
func (p *proc) kill() {
	if !p.exited() {
		syscall.Kill(-p.cmd.Process.Pid, syscall.SIGKILL)
	}
	select {
	case <-p.done:
	case <-time.After(10 * time.Second):
	}
}

func (p *proc) logTail(n int) string {
	b, _ := os.ReadFile(p.logPath)
	lines := strings.Split(strings.TrimRight(string(b), "\n"), "\n")
	if len(lines) > n {
		lines = append([]string{fmt.Sprintf("[... %d lines]", len(lines)-n)}, lines[len(lines)-n:]...)
	}
	return strings.Join(lines, "\n")
}

// farm is the suite's shared farm: a coordinator process, its client and the workers.
type farm struct {
	bin   string
	addr  string
	coord *proc
	c     *client.Client

	mu       sync.Mutex
	workers  []*proc
	restarts int
}

// suiteFarm returns the shared farm, starting it on first use; it fails t if it cannot.
func suiteFarm(t *testing.T) *farm {
	t.Helper()
	sharedOnce.Do(func() { shared, sharedErr = startFarm() })
	if sharedErr != nil {
		t.Fatal(sharedErr)
	}
	return shared
}

func startFarm() (*farm, error) {
	bin, err := binDir()
	if err != nil {
		return nil, err
	}
	if scratch, err = os.MkdirTemp("", "stiff-suite-"); err != nil {
		return nil, err
	}
	addrc := make(chan string, 1)
	coord, err := startProc("coordinator", filepath.Join(bin, "farm"), []string{
		"coordinator", "--listen", "127.0.0.1:0", "--lease-duration", "5s",
		"--data-dir", filepath.Join(scratch, "data"),
	}, func(line string) {
		if _, addr, ok := strings.Cut(line, "coordinator listening on "); ok {
			select {
			case addrc <- strings.TrimSpace(addr):
			default:
			}
		}
	})
	if err != nil {
		return nil, err
	}
	f := &farm{bin: bin, coord: coord}
	select {
	case f.addr = <-addrc:
	case <-coord.done:
		return nil, fmt.Errorf("farm coordinator exited before listening: %v\n%s", coord.err, coord.logTail(40))
	case <-time.After(15 * time.Second):
		coord.kill()
		return nil, fmt.Errorf("farm coordinator did not say `coordinator listening on` within 15s")
	}
	if f.c, err = client.Dial(f.addr); err != nil {
		coord.kill()
		return nil, err
	}
	for i := 0; i < suiteWorkers; i++ {
		w, err := f.startWorker(i)
		if err != nil {
			f.stop()
			return nil, err
		}
		f.workers = append(f.workers, w)
	}
	return f, nil
}

// startWorker runs worker number i with one render thread (two workers on two cores) and a
// cache folder shared by the suite's workers, as workers on one host share it by default.
func (f *farm) startWorker(i int) (*proc, error) {
	name := fmt.Sprintf("worker-%d", i+1)
	return startProc(name, filepath.Join(f.bin, "farm-worker"), []string{
		"--coordinator", f.addr,
		"--cache-dir", filepath.Join(scratch, "cache"),
		"--threads", "1",
		"--name", name,
	}, nil)
}

func (f *farm) stop() {
	if f.c != nil {
		f.c.Close()
	}
	for _, w := range f.workers {
		w.kill()
	}
	f.coord.kill()
}

// reviveWorkers restarts any worker that has died (a crash in an earlier case must not
// take the later cases down with it) and returns the names of those it restarted.
func (f *farm) reviveWorkers() ([]string, error) {
	f.mu.Lock()
	defer f.mu.Unlock()
	var revived []string
	for i, w := range f.workers {
		if !w.exited() {
			continue
		}
		nw, err := f.startWorker(i)
		if err != nil {
			return revived, err
		}
		f.workers[i] = nw
		f.restarts++
		revived = append(revived, fmt.Sprintf("%s (exited: %v)", w.name, w.err))
	}
	return revived, nil
}

// deadWorkers lists the workers that have exited, with their log tails.
func (f *farm) deadWorkers() []string {
	f.mu.Lock()
	defer f.mu.Unlock()
	var dead []string
	for _, w := range f.workers {
		if w.exited() {
			dead = append(dead, fmt.Sprintf("%s exited: %v\n--- %s log ---\n%s", w.name, w.err, w.name, w.logTail(30)))
		}
	}
	return dead
}

// rendered is the result of one case's render.
type rendered struct {
	job     *pb.Job
	img     *image
	elapsed time.Duration // from submit until the job ended
}

// render submits sc, waits up to timeout for the job to end, downloads the final EXR and
// reads it. It fails t (naming the case) if the job does not succeed, if a worker dies
// while it runs, or if the EXR cannot be read.
func (f *farm) render(t *testing.T, name string, sc *pb.Scene, timeout time.Duration) *rendered {
	t.Helper()
	if revived, err := f.reviveWorkers(); err != nil {
		t.Fatalf("case %s: restarting dead workers: %v", name, err)
	} else if len(revived) > 0 {
		t.Logf("case %s: restarted workers left dead by an earlier case: %s", name, strings.Join(revived, "; "))
	}
	if sc.Name == "" {
		sc.Name = "stiff-" + name
	}
	start := time.Now()
	ctx, cancel := context.WithTimeout(context.Background(), timeout)
	defer cancel()
	job, err := f.c.Submit(ctx, sc)
	if err != nil {
		t.Fatalf("case %s: submit: %v", name, err)
	}
	ended, err := f.c.Watch(ctx, job.GetId(), nil)
	elapsed := time.Since(start)
	if dead := f.deadWorkers(); len(dead) > 0 {
		t.Errorf("case %s: a worker died during the render (a crash):\n%s", name, strings.Join(dead, "\n"))
	}
	if err != nil {
		last, _ := f.c.GetJob(context.Background(), job.GetId())
		f.cancel(job.GetId())
		t.Fatalf("case %s: job %s did not end within %s: %v (last seen: %v)\n%s",
			name, job.GetId(), timeout, err, last, f.logs())
	}
	if ended.GetState() != pb.JobState_JOB_STATE_SUCCEEDED {
		t.Fatalf("case %s: job %s ended %v: %s\n%s", name, job.GetId(), ended.GetState(), ended.GetError(), f.logs())
	}
	var exr []byte
	for _, a := range ended.GetOutputs() {
		if a.GetName() == "image.exr" {
			var b strings.Builder
			if _, err := f.c.Download(context.Background(), a.GetDigest(), &b); err != nil {
				t.Fatalf("case %s: download image.exr: %v", name, err)
			}
			exr = []byte(b.String())
		}
	}
	if exr == nil {
		t.Fatalf("case %s: job %s has no image.exr (outputs: %v)", name, job.GetId(), ended.GetOutputs())
	}
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
	f.c.Cancel(ctx, jobID)
}

// logs is the tail of every process's log, for a failure message.
func (f *farm) logs() string {
	f.mu.Lock()
	defer f.mu.Unlock()
	var b strings.Builder
	for _, p := range append([]*proc{f.coord}, f.workers...) {
		fmt.Fprintf(&b, "--- %s log ---\n%s\n", p.name, p.logTail(20))
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
