package main

import (
	"bufio"
	"context"
	"crypto/rand"
	"errors"
	"fmt"
	"os"
	"os/exec"
	"path/filepath"
	"runtime"
	"strconv"
	"strings"
	"syscall"
	"time"

	"photonfarm/client"
	"photonfarm/coordinator"
)

var renderVerb = &verb{
	name:    "render",
	args:    "SCENE|MODEL -o OUTDIR [--name NAME] [--exposure STOPS] [--width N] [--height N] [--workers N] [--worker-bin PATH] [--asset-root DIR] [--dashboard-listen ADDR | --no-dashboard] [--report]",
	summary: "render a scene on a local all-in-one farm",
	run:     runRender,
}

const workerBinName = "farm-worker"

// How long stopping may take before it turns forceful.
const (
	workerStopTimeout      = 30 * time.Second
	coordinatorStopTimeout = 10 * time.Second
)

func runRender(ctx context.Context, e *env, args []string) (err error) {
	fs := newFlags("render", e)
	out := fs.String("o", "out", "output `folder` (created if missing)")
	name := outputNameFlag(fs)
	workers := fs.Int("workers", runtime.NumCPU(), "number of farm-worker processes")
	threads := fs.Int("threads", 0, "render threads per worker (0: the CPUs divided among the workers)")
	workerBin := fs.String("worker-bin", "", "`path` of farm-worker (default: next to farm, else $PATH)")
	lease := fs.Duration("lease-duration", coordinator.DefaultLeaseDuration, "task lease duration")
	assetRoot := assetRootFlag(fs)
	imports := importFlags(fs)
	dashListen := fs.String("dashboard-listen", "127.0.0.1:0", "serve the web dashboard of the local farm on this HTTP `address` (port 0 picks a free one)")
	noDash := fs.Bool("no-dashboard", false, "do not serve the web dashboard")
	exposure := exposureFlag(fs)
	report := fs.Bool("report", false, "when the job ends, print its error against run time, round by round (as farm report does)")
	pos, err := parse(fs, args, 1, 1)
	if err != nil {
		return err
	}
	if *workers < 1 {
		return usageErrorf("render: --workers must be at least 1, got %d", *workers)
	}
	if *threads < 0 {
		return usageErrorf("render: --threads must not be negative, got %d", *threads)
	}
	if *threads == 0 {
		*threads = max(1, runtime.NumCPU() / *workers)
	}
	scenePath := pos[0]

	// Everything that can be checked without a farm is checked first.
	sf, cleanup, err := checkScene(ctx, e.stdout, scenePath, *assetRoot, imports())
	if err != nil {
		return err
	}
	defer cleanup()
	if err := checkOutputDir(*out); err != nil {
		return err
	}
	bin, err := findWorkerBin(*workerBin)
	if err != nil {
		return err
	}
	if *exposure != nil {
		setExposure(sf.Scene, **exposure)
	}

	farm, err := startLocalFarm(bin, *workers, *threads, *lease)
	if err != nil {
		return err
	}
	defer func() {
		if serr := farm.stop(); serr != nil && err == nil {
			err = serr
		}
		if err != nil && ctx.Err() != nil {
			err = &exitError{code: exitInterrupted, err: errors.New("interrupted; the local farm was stopped")}
		}
	}()

	if !*noDash {
		dash, err := startRenderDashboard(farm, *dashListen)
		if err != nil {
			return err
		}
		// Deferred after farm.stop, so it runs first: the dashboard's streams end before
		// the coordinator does.
		defer func() {
			if serr := dash.stop(); serr != nil && err == nil {
				err = serr
			}
		}()
		fmt.Fprintf(e.stdout, "dashboard on %s\n", dash.url)
		fmt.Fprintf(e.stdout, "dashboard token: %s (this farm's client token, random for this run: log in with it)\n", farm.clientToken)
	}

	// The job is followed under a context that also ends if every worker exits.
	jobCtx, cancel := context.WithCancelCause(ctx)
	defer cancel(nil)
	go func() {
		select {
		case <-farm.allExited:
			cancel(farm.exitedError())
		case <-jobCtx.Done():
		}
	}()
	cause := func(err error) error {
		if c := context.Cause(jobCtx); c != nil && ctx.Err() == nil && !errors.Is(c, context.Canceled) {
			return c
		}
		return err
	}

	c, err := client.Dial(farm.coord.addr, client.WithToken(farm.clientToken))
	if err != nil {
		return err
	}
	defer c.Close()
	if err := c.Upload(jobCtx, sf); err != nil {
		return cause(err)
	}
	job, err := c.Submit(jobCtx, sf.Scene, client.WithRequestID(client.NewRequestID()))
	if err != nil {
		return cause(err)
	}
	fmt.Fprintf(e.stdout, "rendering %s as job %s on %d workers × %d threads\n", scenePath, job.GetId(), *workers, *threads)
	if err := watchJob(jobCtx, e, c, job.GetId()); err != nil {
		return cause(err)
	}
	paths, err := c.FetchAs(jobCtx, job.GetId(), *out, *name)
	if err != nil {
		return cause(err)
	}
	for _, p := range paths {
		fmt.Fprintln(e.stdout, p)
	}
	if *report {
		// The local farm ends with this command, so its job's report is printed now or never.
		done, err := c.GetJob(jobCtx, job.GetId())
		if err != nil {
			return cause(err)
		}
		printReport(e.stdout, done)
	}
	return nil
}

// checkOutputDir makes the output folder (FetchAs would at the end) and checks that
// files can be created in it, so that a render never runs only to find that its image
// cannot be written.
func checkOutputDir(dir string) error {
	if fi, err := os.Stat(dir); err == nil && !fi.IsDir() {
		return usageErrorf("render: -o %s is a file: -o names the folder the EXR and the PNG are written to", dir)
	}
	if err := os.MkdirAll(dir, 0o755); err != nil {
		return usageErrorf("render: -o: %v", err)
	}
	f, err := os.CreateTemp(dir, ".farm-render-check-*")
	if err != nil {
		return usageErrorf("render: -o %s: cannot write there: %v", dir, err)
	}
	f.Close()
	return os.Remove(f.Name())
}

// startRenderDashboard serves the dashboard of the local farm on listen, logging to
// dashboard.log in the farm's folder.
func startRenderDashboard(farm *localFarm, listen string) (*embeddedDashboard, error) {
	logf, err := os.Create(filepath.Join(farm.dir, "dashboard.log"))
	if err != nil {
		return nil, err
	}
	defer logf.Close() // the logger writes through its own reference until stop
	d, err := startEmbeddedDashboard(farm.coord.addr, listen, logf)
	if err != nil {
		return nil, usageErrorf("render: %v", err)
	}
	return d, nil
}

// findWorkerBin returns the farm-worker to run: flag, else next to this executable, else
// on $PATH.
func findWorkerBin(flagValue string) (string, error) {
	if flagValue != "" {
		if _, err := os.Stat(flagValue); err != nil {
			return "", usageErrorf("render: --worker-bin: %v", err)
		}
		return flagValue, nil
	}
	if exe, err := os.Executable(); err == nil {
		if exe, err = filepath.EvalSymlinks(exe); err == nil {
			p := filepath.Join(filepath.Dir(exe), workerBinName)
			if st, err := os.Stat(p); err == nil && !st.IsDir() {
				return p, nil
			}
		}
	}
	if p, err := exec.LookPath(workerBinName); err == nil {
		return p, nil
	}
	return "", fmt.Errorf("render: %s not found: pass --worker-bin, or put it next to the farm executable or on $PATH (build it with `make build`)", workerBinName)
}

// localFarm is an embedded coordinator and its worker processes, in a temporary folder.
type localFarm struct {
	dir       string
	coord     *embeddedCoordinator
	workers   []*workerProc
	allExited chan struct{}
	// Even a local farm is authenticated: random tokens, the worker's passed to the
	// worker processes in their environment (not on their command line, which other
	// users of the host can read).
	clientToken, workerToken string
}

type workerProc struct {
	cmd     *exec.Cmd
	logPath string
	done    chan struct{} // closed when the process has exited
	err     error         // its exit status, once done
}

func startLocalFarm(bin string, n, threads int, lease time.Duration) (f *localFarm, err error) {
	dir, err := os.MkdirTemp("", "farm-render-*")
	if err != nil {
		return nil, err
	}
	f = &localFarm{dir: dir, allExited: make(chan struct{}), clientToken: randomToken(), workerToken: randomToken()}
	defer func() {
		if err != nil {
			f.stop()
		}
	}()
	logf, err := os.Create(filepath.Join(dir, "coordinator.log"))
	if err != nil {
		return f, err
	}
	defer logf.Close() // the coordinator's logger keeps its own reference until stop
	f.coord, err = startEmbedded(filepath.Join(dir, "coordinator"), lease, logf, f.clientToken, f.workerToken)
	if err != nil {
		return f, fmt.Errorf("render: start the coordinator: %w", err)
	}
	for i := range n {
		w, err := startWorker(bin, f.coord.addr, f.workerToken, filepath.Join(dir, fmt.Sprintf("worker-%d", i)), threads, i)
		if err != nil {
			return f, fmt.Errorf("render: start %s: %w", bin, err)
		}
		f.workers = append(f.workers, w)
	}
	go func() {
		for _, w := range f.workers {
			<-w.done
		}
		close(f.allExited)
	}()
	return f, nil
}

// randomToken returns a token of at least 128 random bits (crypto/rand).
func randomToken() string { return rand.Text() }

func startWorker(bin, addr, token, dir string, threads, i int) (*workerProc, error) {
	if err := os.MkdirAll(filepath.Join(dir, "cache"), 0o755); err != nil {
		return nil, err
	}
	logPath := filepath.Join(dir, "worker.log")
	logf, err := os.Create(logPath)
	if err != nil {
		return nil, err
	}
	defer logf.Close()
	host, _ := os.Hostname()
	cmd := exec.Command(bin,
		"--coordinator", addr,
		"--cache-dir", filepath.Join(dir, "cache"),
		"--threads", strconv.Itoa(threads),
		"--name", fmt.Sprintf("%s-local-%d", host, i))
	cmd.Env = append(os.Environ(), "FARM_WORKER_TOKEN="+token)
	cmd.Stdout, cmd.Stderr = logf, logf
	// A process group of its own: Ctrl-C reaches farm only, which stops the workers in
	// order; and the kernel kills the worker if farm dies without stopping it.
	cmd.SysProcAttr = &syscall.SysProcAttr{Setpgid: true, Pdeathsig: syscall.SIGKILL}
	if err := cmd.Start(); err != nil {
		return nil, err
	}
	w := &workerProc{cmd: cmd, logPath: logPath, done: make(chan struct{})}
	go func() {
		w.err = cmd.Wait()
		close(w.done)
	}()
	return w, nil
}

// exitedError says that every worker exited, with the last line of the first one's log.
func (f *localFarm) exitedError() error {
	w := f.workers[0]
	return fmt.Errorf("all %d workers exited before the job ended (worker 0: %v: %s)",
		len(f.workers), w.err, lastLine(w.logPath))
}

func lastLine(path string) string {
	fh, err := os.Open(path)
	if err != nil {
		return err.Error()
	}
	defer fh.Close()
	last := "(no output)"
	sc := bufio.NewScanner(fh)
	for sc.Scan() {
		if l := strings.TrimSpace(sc.Text()); l != "" {
			last = l
		}
	}
	return last
}

// stop ends the workers (SIGTERM: each finishes its task, says goodbye and exits; SIGKILL
// after workerStopTimeout), then the coordinator, then removes the temporary folder.
func (f *localFarm) stop() error {
	for _, w := range f.workers {
		syscall.Kill(-w.cmd.Process.Pid, syscall.SIGTERM)
	}
	deadline := time.After(workerStopTimeout)
	var errs []error
	for i, w := range f.workers {
		select {
		case <-w.done:
		case <-deadline:
			syscall.Kill(-w.cmd.Process.Pid, syscall.SIGKILL)
			<-w.done
			errs = append(errs, fmt.Errorf("worker %d did not stop within %s and was killed", i, workerStopTimeout))
		}
	}
	if f.coord != nil {
		if err := f.coord.stop(coordinatorStopTimeout); err != nil {
			errs = append(errs, err)
		}
	}
	if err := os.RemoveAll(f.dir); err != nil {
		errs = append(errs, err)
	}
	return errors.Join(errs...)
}
