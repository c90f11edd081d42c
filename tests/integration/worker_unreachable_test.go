package integration

import (
	"path/filepath"
	"strings"
	"syscall"
	"testing"
	"time"

	"photonfarm/tests/farmtest"
)

// TestWorkerWithoutCoordinatorSaysSoAndRetries: a real farm-worker pointed at a closed
// port logs "cannot reach coordinator at ADDR: ...; retrying" within 5 s, says it again
// (it keeps retrying, with backoff, instead of exiting), and still stops at SIGTERM.
func TestWorkerWithoutCoordinatorSaysSoAndRetries(t *testing.T) {
	addr := farmtest.ClosedAddress(t)
	lines := make(chan string, 64)
	start := time.Now()
	w := farmtest.Start(t, "worker", filepath.Join(farmtest.BinDir(t), "farm-worker"), []string{
		"--coordinator", addr, "--cache-dir", t.TempDir(), "--threads", "1",
	}, func(line string) {
		if strings.Contains(line, "cannot reach coordinator at "+addr+": ") && strings.Contains(line, "; retrying") {
			select {
			case lines <- line:
			default:
			}
		}
	})
	for i, within := range []time.Duration{5 * time.Second, 15 * time.Second} {
		select {
		case line := <-lines:
			t.Logf("after %v: %s", time.Since(start).Round(time.Millisecond), line)
		case <-w.Done():
			t.Fatalf("farm-worker exited (%v) instead of retrying:\n%s", w.Err(), w.LogTail(20))
		case <-time.After(within):
			t.Fatalf("no %s 'cannot reach coordinator at %s: ...; retrying' line within %v:\n%s",
				[]string{"first", "second"}[i], addr, within, w.LogTail(20))
		}
		if i == 0 && time.Since(start) > 5*time.Second {
			t.Errorf("the first line came after %v, want within 5 s", time.Since(start))
		}
	}
	w.Kill(syscall.SIGTERM)
	select {
	case <-w.Done():
	case <-time.After(10 * time.Second):
		t.Fatal("farm-worker did not stop within 10 s of SIGTERM while retrying")
	}
}
