package farmtest

import (
	"fmt"
	"path/filepath"
	"slices"
	"strings"
	"syscall"
	"testing"
	"time"

	"photonfarm/client"
)

// LeaseDuration is the coordinator's --lease-duration in a test farm: short, so that the
// lease of a killed worker expires within the test's patience. A later --lease-duration in
// StartFarm's coordArgs wins (the flag package keeps the last value).
const LeaseDuration = "2s"

// Farm is a `farm coordinator` process and a client connected to it. Workers are started
// with StartWorker. A Farm is used from the test's goroutine: its methods fail the test.
type Farm struct {
	Bin    string // $FARM_BIN_DIR
	Addr   string // where the coordinator listens, HOST:PORT
	Client *client.Client

	coord    *Proc
	wrap     []string // the command the coordinator runs through, if any (StartFarmIn)
	args     []string // the coordinator's flags after --listen, kept for restarts
	starts   int      // coordinators started
	workers  int      // workers started, for their names
	cacheDir string   // the default cache folder parent
}

// StartFarm runs `farm coordinator --listen 127.0.0.1:0 --lease-duration 2s --data-dir
// TMP` followed by coordArgs (more flags: --redis, tokens, TLS, a longer lease), waits for
// it to say where it listens and connects a client with opts (a token, TLS).
func StartFarm(t testing.TB, coordArgs []string, opts ...client.Option) *Farm {
	t.Helper()
	return StartFarmIn(t, nil, coordArgs, opts...)
}

// StartFarmIn is StartFarm with the coordinator run through wrap, a command line that
// runs the command line after it (`unshare ... sh -c 'mount ...; exec "$@"' sh`): the
// coordinator process is what wrap execs, and restarts go through wrap again.
func StartFarmIn(t testing.TB, wrap, coordArgs []string, opts ...client.Option) *Farm {
	t.Helper()
	f := &Farm{
		Bin:      BinDir(t),
		wrap:     wrap,
		args:     append([]string{"--lease-duration", LeaseDuration, "--data-dir", filepath.Join(t.TempDir(), "data")}, coordArgs...),
		cacheDir: t.TempDir(),
	}
	f.Addr, f.coord = f.startCoordinator(t, "127.0.0.1:0")
	c, err := client.Dial(f.Addr, opts...)
	if err != nil {
		t.Fatal(err)
	}
	t.Cleanup(func() { c.Close() })
	f.Client = c
	return f
}

// Coordinator is the running coordinator process.
func (f *Farm) Coordinator() *Proc { return f.coord }

// RestartCoordinator SIGKILLs the coordinator and starts another on the same address with
// the same flags (data folder, Redis); the client and the workers reconnect by themselves.
func (f *Farm) RestartCoordinator(t testing.TB) {
	t.Helper()
	f.coord.Kill(syscall.SIGKILL)
	<-f.coord.Done()
	_, f.coord = f.startCoordinator(t, f.Addr)
}

// StartReplica starts another coordinator with the farm's flags (its Redis, its blob
// store) on a port and a data folder of its own: a replica serving the same jobs, for
// workers and clients given both addresses. It returns the replica's address; the farm's
// Client and Coordinator stay the first coordinator's.
func (f *Farm) StartReplica(t testing.TB) (string, *Proc) {
	t.Helper()
	return f.startCoordinator(t, "127.0.0.1:0", "--data-dir", filepath.Join(t.TempDir(), "data"))
}

// startCoordinator starts a coordinator listening on listen, with the farm's flags and
// then extra, and returns the address it says it listens on and its process.
func (f *Farm) startCoordinator(t testing.TB, listen string, extra ...string) (string, *Proc) {
	t.Helper()
	f.starts++
	name := "coordinator"
	if f.starts > 1 {
		name = fmt.Sprintf("coordinator-%d", f.starts)
	}
	addrc := make(chan string, 1)
	cmd := append(append([]string{filepath.Join(f.Bin, "farm"), "coordinator", "--listen", listen}, f.args...), extra...)
	if len(f.wrap) > 0 {
		cmd = append(slices.Clone(f.wrap), cmd...)
	}
	proc := Start(t, name, cmd[0], cmd[1:],
		func(line string) {
			if _, addr, ok := strings.Cut(line, "coordinator listening on "); ok {
				select {
				case addrc <- strings.TrimSpace(addr):
				default:
				}
			}
		})
	select {
	case addr := <-addrc:
		return addr, proc
	case <-proc.Done():
		t.Fatalf("%s exited before listening: %v", name, proc.Err())
	case <-time.After(15 * time.Second):
		t.Fatalf("%s did not say `coordinator listening on` within 15s", name)
	}
	return "", nil
}

// StartWorker runs a farm-worker with a cache folder of its own, one render thread (the
// machines running these tests have two cores) and extra flags.
func (f *Farm) StartWorker(t testing.TB, extra ...string) *Proc {
	t.Helper()
	return f.StartWorkerWithCache(t, filepath.Join(f.cacheDir, fmt.Sprintf("cache-%d", f.workers+1)), extra...)
}

// StartWorkerWithCache runs a farm-worker with the given cache folder, which several
// workers may share (as workers on one host do by default), one render thread and extra
// flags. Workers are named worker-1, worker-2, ... in the order they start.
func (f *Farm) StartWorkerWithCache(t testing.TB, cache string, extra ...string) *Proc {
	t.Helper()
	return f.StartWorkerVia(t, f.Addr, cache, extra...)
}

// StartWorkerVia is StartWorkerWithCache with the worker told another address for the
// coordinator: a proxy in front of it (Proxy).
func (f *Farm) StartWorkerVia(t testing.TB, coordinator, cache string, extra ...string) *Proc {
	t.Helper()
	f.workers++
	name := fmt.Sprintf("worker-%d", f.workers)
	return Start(t, name, filepath.Join(f.Bin, "farm-worker"), append([]string{
		"--coordinator", coordinator,
		"--cache-dir", cache,
		"--threads", "1",
		"--name", name,
	}, extra...), nil)
}
