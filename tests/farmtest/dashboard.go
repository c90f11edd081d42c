package farmtest

import (
	"os"
	"path/filepath"
	"regexp"
	"testing"
	"time"
)

// TokenFlags writes a client and a worker token file and returns the coordinator flags
// that name them.
func TokenFlags(t testing.TB, clientToken, workerToken string) []string {
	t.Helper()
	dir := t.TempDir()
	clientFile, workerFile := filepath.Join(dir, "client-tokens"), filepath.Join(dir, "worker-tokens")
	if err := os.WriteFile(clientFile, []byte("# clients\n"+clientToken+"\n"), 0o600); err != nil {
		t.Fatal(err)
	}
	if err := os.WriteFile(workerFile, []byte(workerToken+"\n"), 0o600); err != nil {
		t.Fatal(err)
	}
	return []string{"--client-token-file", clientFile, "--worker-token-file", workerFile}
}

var dashboardLine = regexp.MustCompile(`dashboard on (http://\S+)`)

// StartDashboard runs `farm dashboard` in front of the farm's coordinator and returns
// the process and the URL it says it serves on (the line may go to stdout or stderr; both
// reach its log).
func (f *Farm) StartDashboard(t testing.TB) (*Proc, string) {
	t.Helper()
	p := Start(t, "dashboard", filepath.Join(f.Bin, "farm"),
		[]string{"dashboard", "--coordinator", f.Addr, "--listen", "127.0.0.1:0"}, nil)
	deadline := time.Now().Add(15 * time.Second)
	for time.Now().Before(deadline) {
		b, _ := os.ReadFile(p.LogPath)
		if m := dashboardLine.FindSubmatch(b); m != nil {
			return p, string(m[1])
		}
		if p.Exited() {
			t.Fatalf("farm dashboard exited (%v) before saying where it serves:\n%s", p.Err(), p.LogTail(40))
		}
		time.Sleep(20 * time.Millisecond)
	}
	t.Fatalf("farm dashboard did not print `dashboard on http://...` within 15 s:\n%s", p.LogTail(40))
	return nil, ""
}
