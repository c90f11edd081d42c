package farmtest

import (
	"bufio"
	"fmt"
	"os"
	"os/exec"
	"path/filepath"
	"regexp"
	"strconv"
	"strings"
	"sync"
	"syscall"
	"testing"
	"time"
)

// Proc is a process a test started, in a process group of its own, with its stdout and
// stderr going to a log file.
type Proc struct {
	Name    string
	LogPath string
	cmd     *exec.Cmd
	done    chan struct{}
	err     error // exit status, once done is closed
}

// Start runs bin with args. onLine, if not nil, receives each line the process writes to
// stderr (the line goes to the log as well); the coordinator says there where it listens.
// t.Cleanup kills the whole process group and, if the test failed, logs the last lines of
// the process's log.
func Start(t testing.TB, name, bin string, args []string, onLine func(line string)) *Proc {
	t.Helper()
	logPath := filepath.Join(t.TempDir(), name+".log")
	logf, err := os.Create(logPath)
	if err != nil {
		t.Fatal(err)
	}
	cmd := exec.Command(bin, args...)
	cmd.Stdout = logf
	// Pdeathsig: if the test binary dies (a panic, go test's -timeout) before its cleanups
	// run, the kernel kills the process rather than leaving it running.
	cmd.SysProcAttr = &syscall.SysProcAttr{Setpgid: true, Pdeathsig: syscall.SIGKILL}
	pr, pw, err := os.Pipe()
	if err != nil {
		logf.Close()
		t.Fatal(err)
	}
	cmd.Stderr = pw
	if err := cmd.Start(); err != nil {
		logf.Close()
		pr.Close()
		pw.Close()
		t.Fatalf("start %s: %v", name, err)
	}
	pw.Close()
	p := &Proc{Name: name, LogPath: logPath, cmd: cmd, done: make(chan struct{})}
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
	t.Cleanup(func() {
		p.Kill(syscall.SIGKILL)
		select {
		case <-p.done:
		case <-time.After(10 * time.Second):
			t.Errorf("%s did not exit after SIGKILL", name)
		}
		if t.Failed() {
			t.Logf("--- %s log (%s) ---\n%s", name, strings.Join(cmd.Args, " "), p.LogTail(60))
		}
	})
	return p
}

// Done is closed once the process has exited.
func (p *Proc) Done() <-chan struct{} { return p.done }

// Err is the process's exit status (nil for exit 0); valid once Done is closed.
func (p *Proc) Err() error { return p.err }

// ExitCode is the process's exit code (-1 if a signal ended it); valid once Done is closed.
func (p *Proc) ExitCode() int { return p.cmd.ProcessState.ExitCode() }

// Exited reports whether the process has exited.
func (p *Proc) Exited() bool {
	select {
	case <-p.done:
		return true
	default:
		return false
	}
}

// Kill sends sig to the process's group (a worker's children go with it) unless it has
// exited. It does not wait; <-p.Done() does.
func (p *Proc) Kill(sig syscall.Signal) {
	if !p.Exited() {
		syscall.Kill(-p.cmd.Process.Pid, sig)
	}
}

// LogTail is the last n lines of the process's log.
func (p *Proc) LogTail(n int) string {
	b, _ := os.ReadFile(p.LogPath)
	lines := strings.Split(strings.TrimRight(string(b), "\n"), "\n")
	if len(lines) > n {
		lines = append([]string{fmt.Sprintf("[... %d lines]", len(lines)-n)}, lines[len(lines)-n:]...)
	}
	return strings.Join(lines, "\n")
}

var registeredLine = regexp.MustCompile(`\bmsg=registered\b.*?\bworker=(\S+)`)

// WorkerID waits up to timeout for a worker to log its registration (a key=value line
// "msg=registered coordinator=ADDR worker=ID ...") and returns the id, or "" if it did not log that line in time. Tests use it to
// start work only once workers are ready and to know which worker is which; they never
// pass merely because the line is missing. It fails t if the worker exits first.
func (p *Proc) WorkerID(t testing.TB, timeout time.Duration) string {
	t.Helper()
	deadline := time.Now().Add(timeout)
	for time.Now().Before(deadline) {
		b, _ := os.ReadFile(p.LogPath)
		if m := registeredLine.FindSubmatch(b); m != nil {
			return string(m[1])
		}
		if p.Exited() {
			t.Fatalf("%s exited: %v", p.Name, p.err)
		}
		time.Sleep(20 * time.Millisecond)
	}
	t.Logf("%s did not log its registration within %s", p.Name, timeout)
	return ""
}

// PeakRSS is the most resident memory the running process has used so far (VmHWM in
// /proc/PID/status), in bytes.
func (p *Proc) PeakRSS(t testing.TB) uint64 {
	t.Helper()
	status, err := os.ReadFile(fmt.Sprintf("/proc/%d/status", p.cmd.Process.Pid))
	if err != nil {
		t.Fatalf("%s: %v", p.Name, err)
	}
	for _, line := range strings.Split(string(status), "\n") {
		if rest, ok := strings.CutPrefix(line, "VmHWM:"); ok {
			kb, err := strconv.ParseUint(strings.TrimSuffix(strings.TrimSpace(rest), " kB"), 10, 64)
			if err != nil {
				t.Fatalf("%s: VmHWM %q: %v", p.Name, rest, err)
			}
			return kb << 10
		}
	}
	t.Fatalf("%s: no VmHWM in /proc/%d/status", p.Name, p.cmd.Process.Pid)
	return 0
}
