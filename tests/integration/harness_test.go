package integration

import (
	"bufio"
	"context"
	"fmt"
	"os"
	"os/exec"
	"path/filepath"
	"regexp"
	"runtime"
	"strings"
	"sync"
	"syscall"
	"testing"
	"time"

	"google.golang.org/protobuf/proto"

	"photonfarm/client"
	pb "photonfarm/proto/renderfarm/v1"
)

// binDir returns $FARM_BIN_DIR, where `farm` and `farm-worker` are built. These tests
// exist to run the real binaries: without them they fail rather than skip.
func binDir(t testing.TB) string {
	t.Helper()
	dir := os.Getenv("FARM_BIN_DIR")
	if dir == "" {
		t.Fatal("FARM_BIN_DIR is not set: these tests run the built binaries. Build them " +
			"(make build) and run FARM_BIN_DIR=$PWD/build/bin go test ./tests/..., or run make test")
	}
	for _, b := range []string{"farm", "farm-worker"} {
		if _, err := os.Stat(filepath.Join(dir, b)); err != nil {
			t.Fatalf("FARM_BIN_DIR=%s: %v (build with make build)", dir, err)
		}
	}
	abs, err := filepath.Abs(dir)
	if err != nil {
		t.Fatal(err)
	}
	return abs
}

// repoRoot is the module root, two folders above this package.
func repoRoot(t testing.TB) string {
	_, file, _, _ := runtime.Caller(0)
	return filepath.Dir(filepath.Dir(filepath.Dir(file)))
}

// proc is a process the test started, in a process group of its own, with its output
// going to a log file that is shown if the test fails.
type proc struct {
	name    string
	cmd     *exec.Cmd
	logPath string
	done    chan struct{}
	err     error // exit status, once done is closed
}

// start runs bin with args. extraOut, if not nil, receives the process's stderr lines
// (they go to the log as well). Cleanup kills the whole process group.
func start(t *testing.T, name, bin string, args []string, extraOut func(line string)) *proc {
	t.Helper()
	logPath := filepath.Join(t.TempDir(), name+".log")
	logf, err := os.Create(logPath)
	if err != nil {
		t.Fatal(err)
	}
	cmd := exec.Command(bin, args...)
	cmd.Stdout = logf
	cmd.SysProcAttr = &syscall.SysProcAttr{Setpgid: true}
	var pr, pw *os.File
	if extraOut != nil {
		if pr, pw, err = os.Pipe(); err != nil {
			t.Fatal(err)
		}
		cmd.Stderr = pw
	} else {
		cmd.Stderr = logf
	}
	if err := cmd.Start(); err != nil {
		t.Fatalf("start %s: %v", name, err)
	}
	p := &proc{name: name, cmd: cmd, logPath: logPath, done: make(chan struct{})}
	var copying sync.WaitGroup
	if pw != nil {
		pw.Close()
		copying.Add(1)
		go func() {
			defer copying.Done()
			sc := bufio.NewScanner(pr)
			for sc.Scan() {
				fmt.Fprintln(logf, sc.Text())
				extraOut(sc.Text())
			}
			pr.Close()
		}()
	}
	go func() {
		p.err = cmd.Wait()
		copying.Wait()
		logf.Close()
		close(p.done)
	}()
	t.Cleanup(func() {
		p.kill(syscall.SIGKILL)
		select {
		case <-p.done:
		case <-time.After(10 * time.Second):
			t.Errorf("%s did not exit after SIGKILL", name)
		}
		if t.Failed() {
			b, _ := os.ReadFile(logPath)
			t.Logf("--- %s log (%s) ---\n%s", name, strings.Join(cmd.Args, " "), tail(string(b), 60))
		}
	})
	return p
}

func tail(s string, n int) string {
	lines := strings.Split(strings.TrimRight(s, "\n"), "\n")
	if len(lines) > n {
		lines = append([]string{fmt.Sprintf("[... %d lines]", len(lines)-n)}, lines[len(lines)-n:]...)
	}
	return strings.Join(lines, "\n")
}

// kill signals the process's group.
func (p *proc) kill(sig syscall.Signal) {
	select {
	case <-p.done:
	default:
		syscall.Kill(-p.cmd.Process.Pid, sig)
	}
}

func (p *proc) exited() bool {
	select {
	case <-p.done:
		return true
	default:
		return false
	}
}

var registeredLine = regexp.MustCompile(`registered with \S+ as (\S+)`)

// workerID waits up to timeout for the worker to log its registration ("registered with
// ADDR as ID") and returns the id, or "" if it did not log that line in time. Tests use it
// to start work only once workers are ready and to know which worker is which; they never
// pass merely because the line is missing.
func (p *proc) workerID(t *testing.T, timeout time.Duration) string {
	t.Helper()
	deadline := time.Now().Add(timeout)
	for time.Now().Before(deadline) {
		b, _ := os.ReadFile(p.logPath)
		if m := registeredLine.FindSubmatch(b); m != nil {
			return string(m[1])
		}
		if p.exited() {
			t.Fatalf("%s exited: %v", p.name, p.err)
		}
		time.Sleep(20 * time.Millisecond)
	}
	t.Logf("%s did not log its registration within %s", p.name, timeout)
	return ""
}

// farm is a coordinator process and a client connected to it.
type farm struct {
	t       *testing.T
	bin     string
	addr    string
	coord   *proc
	c       *client.Client
	workers int
}

// startFarm runs `farm coordinator --listen 127.0.0.1:0 --lease-duration 2s` and waits
// for it to say where it listens.
func startFarm(t *testing.T) *farm { return startFarmWith(t, nil) }

// startFarmWith is startFarm with more coordinator flags (coordArgs) and client options
// (a token, TLS) for the test's client.
func startFarmWith(t *testing.T, coordArgs []string, opts ...client.Option) *farm {
	t.Helper()
	bin := binDir(t)
	addrc := make(chan string, 1)
	coord := start(t, "coordinator", filepath.Join(bin, "farm"), append([]string{
		"coordinator", "--listen", "127.0.0.1:0", "--lease-duration", "2s",
		"--data-dir", filepath.Join(t.TempDir(), "data"),
	}, coordArgs...), func(line string) {
		if _, addr, ok := strings.Cut(line, "coordinator listening on "); ok {
			select {
			case addrc <- strings.TrimSpace(addr):
			default:
			}
		}
	})
	var addr string
	select {
	case addr = <-addrc:
	case <-coord.done:
		t.Fatalf("farm coordinator exited before listening: %v", coord.err)
	case <-time.After(15 * time.Second):
		t.Fatal("farm coordinator did not say `coordinator listening on` within 15s")
	}
	c, err := client.Dial(addr, opts...)
	if err != nil {
		t.Fatal(err)
	}
	t.Cleanup(func() { c.Close() })
	return &farm{t: t, bin: bin, addr: addr, coord: coord, c: c}
}

// startWorker runs a farm-worker with a cache folder of its own and one render thread
// (the machines running these tests have two cores).
func (f *farm) startWorker() *proc {
	f.t.Helper()
	return f.startWorkerWithCache(filepath.Join(f.t.TempDir(), "cache"))
}

// startWorkerWithCache runs a farm-worker with the given cache folder, which several
// workers may share (as workers on one host do by default), and extra flags.
func (f *farm) startWorkerWithCache(cache string, extra ...string) *proc {
	f.t.Helper()
	f.workers++
	name := fmt.Sprintf("worker-%d", f.workers)
	return start(f.t, name, filepath.Join(f.bin, "farm-worker"), append([]string{
		"--coordinator", f.addr,
		"--cache-dir", cache,
		"--threads", "1",
		"--name", name,
	}, extra...), nil)
}

// testScene loads scenes/test-small.json through the client (uploading its mesh) and
// changes its film and sampling: width x height pixels in tiles of side tile, spp samples,
// with a global photon map of 20,000 paths in two shards.
func (f *farm) testScene(width, height, tile, spp uint32) *pb.Scene {
	f.t.Helper()
	sc := f.loadScene("test-small.json")
	sc.Film = &pb.Film{Width: width, Height: height, TileSize: tile}
	sc.Sampling.SamplesPerPixel = spp
	// A small global map (the scene has no specular surface), so that these tests of
	// tiles spend their time rendering.
	sc.Photons = &pb.PhotonMapping{GlobalPhotons: 20000, PhotonsPerShard: 10000}
	return sc
}

// loadScene loads scenes/NAME through the client, uploading its meshes.
func (f *farm) loadScene(name string) *pb.Scene {
	f.t.Helper()
	ctx, cancel := context.WithTimeout(context.Background(), 30*time.Second)
	defer cancel()
	sc, err := f.c.LoadSceneFile(ctx, filepath.Join(repoRoot(f.t), "scenes", name))
	if err != nil {
		f.t.Fatal(err)
	}
	return proto.Clone(sc).(*pb.Scene)
}

// render submits sc and waits for the job to end; it fails the test unless the job
// succeeded.
func (f *farm) render(sc *pb.Scene, timeout time.Duration) *pb.Job {
	f.t.Helper()
	job := f.submit(sc)
	return f.wait(job.GetId(), timeout)
}

func (f *farm) submit(sc *pb.Scene) *pb.Job {
	f.t.Helper()
	ctx, cancel := context.WithTimeout(context.Background(), 30*time.Second)
	defer cancel()
	job, err := f.c.Submit(ctx, sc)
	if err != nil {
		f.t.Fatalf("submit: %v", err)
	}
	return job
}

func (f *farm) wait(jobID string, timeout time.Duration) *pb.Job {
	f.t.Helper()
	ctx, cancel := context.WithTimeout(context.Background(), timeout)
	defer cancel()
	job, err := f.c.Watch(ctx, jobID, nil)
	if err != nil {
		last, _ := f.c.GetJob(context.Background(), jobID)
		f.t.Fatalf("job %s: %v (last seen: %v)", jobID, err, last)
	}
	if job.GetState() != pb.JobState_JOB_STATE_SUCCEEDED {
		f.t.Fatalf("job %s ended %v: %s", jobID, job.GetState(), job.GetError())
	}
	return job
}

// output downloads the named artifact ("image.exr", "preview.png") of a succeeded job.
func (f *farm) output(job *pb.Job, name string) []byte {
	f.t.Helper()
	for _, a := range job.GetOutputs() {
		if a.GetName() == name {
			var b strings.Builder
			if _, err := f.c.Download(context.Background(), a.GetDigest(), &b); err != nil {
				f.t.Fatalf("download %s: %v", name, err)
			}
			return []byte(b.String())
		}
	}
	f.t.Fatalf("job %s has no %s output (outputs: %v)", job.GetId(), name, job.GetOutputs())
	return nil
}

func (f *farm) tasks(jobID string) []*pb.Task {
	f.t.Helper()
	tasks, err := f.c.ListTasks(context.Background(), jobID)
	if err != nil {
		f.t.Fatalf("list tasks: %v", err)
	}
	return tasks
}

// runFarm runs the farm CLI with args and returns its exit code, stdout and stderr.
func runFarm(t *testing.T, timeout time.Duration, env []string, args ...string) (code int, stdout, stderr string) {
	t.Helper()
	ctx, cancel := context.WithTimeout(context.Background(), timeout)
	defer cancel()
	cmd := exec.CommandContext(ctx, filepath.Join(binDir(t), "farm"), args...)
	cmd.Env = append(os.Environ(), env...)
	var out, errb strings.Builder
	cmd.Stdout, cmd.Stderr = &out, &errb
	err := cmd.Run()
	if ctx.Err() != nil {
		t.Fatalf("farm %s: did not finish within %s\nstdout: %s\nstderr: %s", strings.Join(args, " "), timeout, out.String(), errb.String())
	}
	if err != nil {
		if ee, ok := err.(*exec.ExitError); ok {
			return ee.ExitCode(), out.String(), errb.String()
		}
		t.Fatalf("farm %s: %v", strings.Join(args, " "), err)
	}
	return 0, out.String(), errb.String()
}
