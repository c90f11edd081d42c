// Package redistest runs a real redis-server for tests: on a free loopback port, in the
// test's temporary directory, killed when the test ends. A machine without redis-server
// fails the test (never skips it), so a missing dependency cannot pass CI silently.
package redistest

import (
	"context"
	"fmt"
	"net"
	"os"
	"os/exec"
	"path/filepath"
	"strconv"
	"testing"
	"time"

	"github.com/redis/go-redis/v9"
)

// Server is a running redis-server.
type Server struct {
	t    testing.TB
	addr string
	args []string
	dir  string
	cmd  *exec.Cmd
	done chan struct{} // closed when cmd has exited
}

// Option configures Start.
type Option func(*config)

type config struct{ appendOnly bool }

// AppendOnly turns the append-only file on (fsync always), so that data survives Restart.
func AppendOnly() Option { return func(c *config) { c.appendOnly = true } }

// Start launches redis-server and waits until it answers PING. It is stopped in
// t.Cleanup.
func Start(t testing.TB, opts ...Option) *Server {
	t.Helper()
	var c config
	for _, o := range opts {
		o(&c)
	}
	bin, err := exec.LookPath("redis-server")
	if err != nil {
		t.Fatalf("redis-server is not on PATH (%v): run scripts/install-deps.sh", err)
	}
	dir := t.TempDir()
	port := freePort(t)
	s := &Server{t: t, addr: net.JoinHostPort("127.0.0.1", strconv.Itoa(port)), dir: dir}
	s.args = []string{"--port", strconv.Itoa(port), "--bind", "127.0.0.1", "--dir", dir, "--save", "",
		"--logfile", filepath.Join(dir, "redis.log")}
	if c.appendOnly {
		s.args = append(s.args, "--appendonly", "yes", "--appendfsync", "always")
	} else {
		s.args = append(s.args, "--appendonly", "no")
	}
	s.start(bin)
	t.Cleanup(s.stop)
	return s
}

// Addr is the server's host:port.
func (s *Server) Addr() string { return s.addr }

// Client returns a client of the server, closed in t.Cleanup.
func (s *Server) Client() *redis.Client {
	c := redis.NewClient(&redis.Options{Addr: s.addr})
	s.t.Cleanup(func() { _ = c.Close() })
	return c
}

// Restart kills the server and starts it again on the same port and directory; with
// AppendOnly it comes back with its data.
func (s *Server) Restart() {
	s.t.Helper()
	s.stop()
	s.start(s.cmd.Path)
}

// Kill stops the server as a crash would, until Revive; clients' calls fail meanwhile.
func (s *Server) Kill() {
	s.t.Helper()
	s.stop()
}

// Revive starts a killed server again on the same port and directory.
func (s *Server) Revive() {
	s.t.Helper()
	s.start(s.cmd.Path)
}

func (s *Server) start(bin string) {
	s.t.Helper()
	s.cmd = exec.Command(bin, s.args...)
	s.cmd.Dir = s.dir
	if err := s.cmd.Start(); err != nil {
		s.t.Fatalf("start redis-server: %v", err)
	}
	s.done = make(chan struct{})
	go func(cmd *exec.Cmd, done chan struct{}) {
		_ = cmd.Wait()
		close(done)
	}(s.cmd, s.done)
	s.waitReady()
}

func (s *Server) waitReady() {
	s.t.Helper()
	c := redis.NewClient(&redis.Options{Addr: s.addr, MaxRetries: -1})
	defer c.Close()
	deadline := time.Now().Add(10 * time.Second)
	for {
		ctx, cancel := context.WithTimeout(context.Background(), time.Second)
		err := c.Ping(ctx).Err()
		cancel()
		if err == nil {
			return
		}
		select {
		case <-s.done:
			s.t.Fatalf("redis-server %v exited before answering PING; its log:\n%s", s.args, s.log())
		default:
		}
		if time.Now().After(deadline) {
			s.t.Fatalf("redis-server on %s did not answer PING: %v; its log:\n%s", s.addr, err, s.log())
		}
		time.Sleep(10 * time.Millisecond)
	}
}

func (s *Server) log() string {
	b, _ := os.ReadFile(filepath.Join(s.dir, "redis.log"))
	return string(b)
}

// stop kills the server (no graceful shutdown: the AOF must hold up to a crash) and
// waits for it to exit.
func (s *Server) stop() {
	select {
	case <-s.done:
		return
	default:
	}
	_ = s.cmd.Process.Kill()
	<-s.done
}

// freePort asks the kernel for a free loopback port. Another process could take it
// before redis-server binds it; tests are not run against such a busy machine.
func freePort(t testing.TB) int {
	t.Helper()
	l, err := net.Listen("tcp", "127.0.0.1:0")
	if err != nil {
		t.Fatalf("find a free port: %v", err)
	}
	defer l.Close()
	return l.Addr().(*net.TCPAddr).Port
}

// LogSlowCommands has the server log every command that runs longer than over (scripts
// included), for SlowestCommand.
func (s *Server) LogSlowCommands(over time.Duration) {
	s.t.Helper()
	c := redis.NewClient(&redis.Options{Addr: s.addr})
	defer c.Close()
	ctx := context.Background()
	for k, v := range map[string]string{"slowlog-log-slower-than": strconv.FormatInt(over.Microseconds(), 10), "slowlog-max-len": "100000"} {
		if err := c.ConfigSet(ctx, k, v).Err(); err != nil {
			s.t.Fatal(err)
		}
	}
	if err := c.Do(ctx, "SLOWLOG", "RESET").Err(); err != nil {
		s.t.Fatal(err)
	}
}

// SlowestCommand returns the longest command logged since the last call (or
// LogSlowCommands), with the start of its arguments, and empties the log.
func (s *Server) SlowestCommand() (time.Duration, string) {
	s.t.Helper()
	c := redis.NewClient(&redis.Options{Addr: s.addr})
	defer c.Close()
	ctx := context.Background()
	logs, err := c.Do(ctx, "SLOWLOG", "GET", "-1").Slice()
	if err != nil {
		s.t.Fatal(err)
	}
	var worst time.Duration
	var what string
	for _, l := range logs {
		e, _ := l.([]any)
		if len(e) < 4 {
			continue
		}
		us, _ := e[2].(int64)
		if d := time.Duration(us) * time.Microsecond; d > worst {
			worst, what = d, fmt.Sprint(e[3])
		}
	}
	if err := c.Do(ctx, "SLOWLOG", "RESET").Err(); err != nil {
		s.t.Fatal(err)
	}
	return worst, what[:min(len(what), 60)]
}
