package integration

import (
	"context"
	"errors"
	"os"
	"os/exec"
	"path/filepath"
	"strings"
	"syscall"
	"testing"
	"time"

	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

// smallDisk mounts a tmpfs of size bytes at a new folder and returns it; it is unmounted
// at cleanup. Mounting needs root, as the compose test does; the test fails without it.
func smallDisk(t *testing.T, size string) string {
	t.Helper()
	dir := filepath.Join(t.TempDir(), "disk")
	if err := os.Mkdir(dir, 0o755); err != nil {
		t.Fatal(err)
	}
	if out, err := exec.Command("mount", "-t", "tmpfs", "-o", "size="+size, "tmpfs", dir).CombinedOutput(); err != nil {
		t.Fatalf("mount a %s tmpfs (needs root): %v: %s", size, err, out)
	}
	t.Cleanup(func() {
		if out, err := exec.Command("umount", "-l", dir).CombinedOutput(); err != nil {
			t.Errorf("umount %s: %v: %s", dir, err, out)
		}
	})
	return dir
}

// fill writes a file in dir until the disk is full and returns its path.
func fill(t *testing.T, dir string) string {
	t.Helper()
	path := filepath.Join(dir, "filler")
	f, err := os.Create(path)
	if err != nil {
		t.Fatal(err)
	}
	defer f.Close()
	block := make([]byte, 64<<10)
	for {
		if _, err := f.Write(block); err != nil {
			if !errors.Is(err, syscall.ENOSPC) {
				t.Fatalf("filling %s: %v, want ENOSPC", dir, err)
			}
			return path
		}
	}
}

// A full disk on the coordinator is nobody's fault: the workers' uploads (and the
// builder's snapshot) fail as resource exhaustion saying the disk is full, no worker is
// blocked, the job ends at its attempt limit with that reason instead of "every worker is
// blocked", and once there is room the same workers render the next job.
func TestCoordinatorDiskFullBlocksNoWorker(t *testing.T) {
	data := smallDisk(t, "4m")
	f := farmtest.StartFarm(t, []string{"--data-dir", data})
	job := f.Submit(t, f.TestScene(t, 32, 32, 16, 1)) // the scene and the mesh are stored
	filler := fill(t, data)
	for range 2 {
		f.StartWorker(t)
	}
	ctx, cancel := context.WithTimeout(context.Background(), 2*time.Minute)
	defer cancel()
	ended, err := f.Client.Watch(ctx, job.GetId(), nil)
	if err != nil {
		t.Fatalf("watch %s: %v", job.GetId(), err)
	}
	t.Logf("job %v (%v): %s", ended.GetState(), ended.GetFailureKind(), ended.GetError())
	if ended.GetState() != pb.JobState_JOB_STATE_FAILED || ended.GetFailureKind() != pb.FailureKind_FAILURE_KIND_RESOURCE_EXHAUSTED ||
		!strings.Contains(ended.GetError(), "the coordinator's disk is full") || len(ended.GetBlockedWorkers()) != 0 {
		t.Errorf("job %v %v %q, blocked %v; want FAILED as resource exhaustion naming the full disk, no worker blocked",
			ended.GetState(), ended.GetFailureKind(), ended.GetError(), ended.GetBlockedWorkers())
	}
	if err := os.Remove(filler); err != nil {
		t.Fatal(err)
	}
	f.Wait(t, f.Submit(t, f.TestScene(t, 32, 32, 16, 1)).GetId(), 2*time.Minute)
}
