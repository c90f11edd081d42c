// Package s3test runs a real S3-compatible object store for tests: SeaweedFS's weed
// (`weed mini`, every service of a one-machine SeaweedFS in one process), built by
// scripts/install-deps.sh from the Go module pinned in scripts/seaweedfs.version. A test
// binary starts one server (Shared) and its tests share it, each under a key prefix of
// its own (URL), so the whole package pays one start-up.
//
// Tests fail, never skip, without the weed binary: run scripts/install-deps.sh.
package s3test

import (
	"context"
	"crypto/rand"
	"encoding/hex"
	"fmt"
	"net"
	"net/url"
	"os"
	"os/exec"
	"path/filepath"
	"regexp"
	"runtime"
	"strconv"
	"strings"
	"sync"
	"syscall"
	"testing"
	"time"

	"photonfarm/coordinator/blobstore"
)

// Bucket is the bucket every server has.
const Bucket = "farm"

// Region is what the URLs say; SeaweedFS accepts any.
const Region = "us-east-1"

// StartTimeout bounds a server's start on a loaded machine.
const StartTimeout = 90 * time.Second

// Server is a running weed.
type Server struct {
	// Endpoint is the S3 API's URL, http://127.0.0.1:PORT.
	Endpoint string
	dir      string
	bin      string
	args     []string
	sockets  []string // the ones weed leaves in /tmp
	cmd      *exec.Cmd
	exited   chan struct{}
	logPath  string
}

// Binary finds weed: $FARM_WEED, else where scripts/install-deps.sh builds it
// ($FARM_TOOLS_DIR, default the user's cache folder photonfarm/tools, then
// seaweedfs-VERSION/weed), else weed on PATH.
func Binary() (string, error) {
	if p := os.Getenv("FARM_WEED"); p != "" {
		return p, nil
	}
	version, err := Version()
	if err != nil {
		return "", err
	}
	tools := os.Getenv("FARM_TOOLS_DIR")
	if tools == "" {
		cache, err := os.UserCacheDir()
		if err != nil {
			return "", err
		}
		tools = filepath.Join(cache, "photonfarm", "tools")
	}
	p := filepath.Join(tools, "seaweedfs-"+version, "weed")
	if _, err := os.Stat(p); err == nil {
		return p, nil
	}
	if p, err := exec.LookPath("weed"); err == nil {
		return p, nil
	}
	return "", fmt.Errorf("no SeaweedFS weed binary at %s nor on PATH: run scripts/install-deps.sh (or set FARM_WEED)", p)
}

// Version is the SeaweedFS module version scripts/seaweedfs.version pins.
func Version() (string, error) {
	_, here, _, _ := runtime.Caller(0)
	root := filepath.Join(filepath.Dir(here), "..", "..", "..")
	b, err := os.ReadFile(filepath.Join(root, "scripts", "seaweedfs.version"))
	if err != nil {
		return "", err
	}
	return strings.TrimSpace(string(b)), nil
}

// freePorts asks the kernel for n free loopback ports.
func freePorts(n int) ([]int, error) {
	var ports []int
	var held []net.Listener
	defer func() {
		for _, l := range held {
			l.Close()
		}
	}()
	for range n {
		l, err := net.Listen("tcp", "127.0.0.1:0")
		if err != nil {
			return nil, err
		}
		held = append(held, l)
		ports = append(ports, l.Addr().(*net.TCPAddr).Port)
	}
	return ports, nil
}

// The keys of the one identity of every server a test binary starts.
var key, secret = randomHex(10), randomHex(20)

// Start starts a weed in dir with the bucket Bucket and one identity, whose keys it puts
// in the process's AWS_ACCESS_KEY_ID and AWS_SECRET_ACCESS_KEY (the AWS SDK's usual
// credentials, as a coordinator gets them: processes the test starts inherit them). It
// answers before Start returns.
func Start(dir string) (*Server, error) {
	bin, err := Binary()
	if err != nil {
		return nil, err
	}
	config := fmt.Sprintf(`{"identities":[{"name":"farm","credentials":[{"accessKey":%q,"secretKey":%q}],`+
		`"actions":["Admin","Read","Write","List","Tagging"]}]}`, key, secret)
	if err := os.WriteFile(filepath.Join(dir, "s3.json"), []byte(config), 0o600); err != nil {
		return nil, err
	}
	p, err := freePorts(11)
	if err != nil {
		return nil, err
	}
	args := []string{"mini", "-dir=" + filepath.Join(dir, "data"), "-ip=127.0.0.1", "-ip.bind=127.0.0.1",
		"-master.telemetry=false", "-webdav=false", "-admin.ui=false",
		"-s3.config=" + filepath.Join(dir, "s3.json"), "-bucket=" + Bucket,
		"-s3.port.iceberg=0", "-s3.port.lance=0",
		"-master.port=" + strconv.Itoa(p[0]), "-master.port.grpc=" + strconv.Itoa(p[1]),
		"-volume.port=" + strconv.Itoa(p[2]), "-volume.port.grpc=" + strconv.Itoa(p[3]),
		"-filer.port=" + strconv.Itoa(p[4]), "-filer.port.grpc=" + strconv.Itoa(p[5]),
		"-s3.port=" + strconv.Itoa(p[6]), "-s3.port.grpc=" + strconv.Itoa(p[7]),
		"-metricsPort=0", "-debug.port=" + strconv.Itoa(p[8]),
		"-admin.port=" + strconv.Itoa(p[9]), "-admin.port.grpc=" + strconv.Itoa(p[10]), "-admin.port.legacy=0",
		"-filer.localSocket=" + filepath.Join(dir, "filer.sock"), "-s3.localSocket=" + filepath.Join(dir, "s3.sock"),
	}
	// weed puts its services' gRPC sockets in /tmp whatever it is told; Stop removes them.
	var sockets []string
	for _, g := range []struct {
		service string
		port    int
	}{{"master", p[1]}, {"volume", p[3]}, {"filer", p[5]}, {"s3", p[7]}, {"admin", p[10]}} {
		sockets = append(sockets, fmt.Sprintf("/tmp/seaweedfs-%s-grpc-%d.sock", g.service, g.port))
	}
	if err := os.MkdirAll(filepath.Join(dir, "data"), 0o755); err != nil {
		return nil, err
	}
	s := &Server{Endpoint: "http://127.0.0.1:" + strconv.Itoa(p[6]), dir: dir, bin: bin, args: args,
		logPath: filepath.Join(dir, "weed.log"), sockets: sockets}
	if err := s.start(); err != nil {
		return nil, err
	}
	os.Setenv("AWS_ACCESS_KEY_ID", key)
	os.Setenv("AWS_SECRET_ACCESS_KEY", secret)
	// Nothing else of the machine's AWS setup is read, and the SDK never asks a cloud's
	// metadata service for credentials.
	os.Setenv("AWS_CONFIG_FILE", filepath.Join(dir, "no-aws-config"))
	os.Setenv("AWS_SHARED_CREDENTIALS_FILE", filepath.Join(dir, "no-aws-credentials"))
	os.Setenv("AWS_EC2_METADATA_DISABLED", "true")
	os.Unsetenv("AWS_SESSION_TOKEN")
	os.Unsetenv("AWS_PROFILE")
	if err := s.waitReady(); err != nil {
		s.Stop()
		return nil, err
	}
	return s, nil
}

// start runs weed, its output appended to the log.
func (s *Server) start() error {
	log, err := os.OpenFile(s.logPath, os.O_CREATE|os.O_WRONLY|os.O_APPEND, 0o644)
	if err != nil {
		return err
	}
	defer log.Close()
	cmd := exec.Command(s.bin, s.args...)
	cmd.Dir = s.dir
	cmd.Stdout, cmd.Stderr = log, log
	// The server dies with the test binary, however that ends.
	cmd.SysProcAttr = &syscall.SysProcAttr{Pdeathsig: syscall.SIGKILL, Setpgid: true}
	if err := cmd.Start(); err != nil {
		return fmt.Errorf("start %s: %w", s.bin, err)
	}
	s.cmd, s.exited = cmd, make(chan struct{})
	go func() { cmd.Wait(); close(s.exited) }()
	return nil
}

// Restart starts a stopped server again on the same ports and data.
func (s *Server) Restart() error {
	if err := s.start(); err != nil {
		return err
	}
	return s.waitReady()
}

// waitReady waits until the bucket answers the credentials: weed makes it just before
// its S3 API listens.
func (s *Server) waitReady() error {
	deadline := time.Now().Add(StartTimeout)
	var err error
	for time.Now().Before(deadline) {
		select {
		case <-s.exited:
			return fmt.Errorf("weed exited while starting: %s", s.LogTail())
		default:
		}
		ctx, cancel := context.WithTimeout(context.Background(), 5*time.Second)
		var st *blobstore.Store
		st, err = blobstore.Open(ctx, s.URL("")+"&stall_timeout=2s", 0)
		cancel()
		if err == nil {
			return st.Close()
		}
		time.Sleep(200 * time.Millisecond)
	}
	return fmt.Errorf("weed did not answer at %s within %s (%v): %s", s.Endpoint, StartTimeout, err, s.LogTail())
}

// LogTail is the end of the server's log, for failure messages.
func (s *Server) LogTail() string {
	b, _ := os.ReadFile(s.logPath)
	return string(b[max(0, len(b)-2000):])
}

// Stop kills the server (SIGKILL, as a crash would) and waits for it to exit.
func (s *Server) Stop() {
	_ = syscall.Kill(-s.cmd.Process.Pid, syscall.SIGKILL)
	<-s.exited
	for _, p := range s.sockets {
		os.Remove(p)
	}
}

// Pause freezes the server (SIGSTOP): it keeps its connections and answers nothing,
// as a hung or cut-off server does. Resume undoes it.
func (s *Server) Pause() error  { return syscall.Kill(-s.cmd.Process.Pid, syscall.SIGSTOP) }
func (s *Server) Resume() error { return syscall.Kill(-s.cmd.Process.Pid, syscall.SIGCONT) }

// Host is the S3 API's host:port.
func (s *Server) Host() string { return strings.TrimPrefix(s.Endpoint, "http://") }

// URL is a blob store URL (blobstore.Open) for the bucket under prefix.
func (s *Server) URL(prefix string) string { return URL(s.Endpoint, prefix) }

// URL is a blob store URL for the bucket Bucket of the S3 API at endpoint (a server's,
// or a Proxy's in front of it), under prefix.
func URL(endpoint, prefix string) string {
	q := url.Values{"endpoint": {endpoint}, "region": {Region}, "use_path_style": {"true"}}
	if prefix != "" {
		q.Set("prefix", prefix)
	}
	return "s3://" + Bucket + "?" + q.Encode()
}

var unsafeKey = regexp.MustCompile(`[^A-Za-z0-9_.-]+`)

// TestURL is URL with a prefix no other test uses: the test's name and a random suffix.
func (s *Server) TestURL(t testing.TB) string {
	return s.URL(unsafeKey.ReplaceAllString(t.Name(), "_") + "-" + randomHex(4) + "/")
}

func randomHex(n int) string {
	b := make([]byte, n)
	rand.Read(b)
	return hex.EncodeToString(b)
}

var shared struct {
	once sync.Once
	srv  *Server
	dir  string
	err  error
}

// Shared is the test binary's server, started on first use and stopped by Main.
func Shared(t testing.TB) *Server {
	t.Helper()
	shared.once.Do(func() {
		start := time.Now()
		if shared.dir, shared.err = os.MkdirTemp("", "s3test-"); shared.err != nil {
			return
		}
		shared.srv, shared.err = Start(shared.dir)
		if shared.err == nil {
			fmt.Fprintf(os.Stderr, "s3test: weed at %s started in %.1fs\n", shared.srv.Endpoint, time.Since(start).Seconds())
		}
	})
	if shared.err != nil {
		t.Fatalf("s3test: %v", shared.err)
	}
	return shared.srv
}

// Main runs a package's tests (call it from TestMain) and then stops the shared server.
func Main(m *testing.M) {
	code := m.Run()
	if shared.srv != nil {
		shared.srv.Stop()
	}
	if shared.dir != "" {
		os.RemoveAll(shared.dir)
	}
	os.Exit(code)
}
