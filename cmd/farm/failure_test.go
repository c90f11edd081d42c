package main

import (
	"os"
	"path/filepath"
	"strings"
	"testing"
	"time"

	pb "photonfarm/proto/renderfarm/v1"
)

func TestSubmitAndRenderRefuseABrokenMeshInOneLineBeforeTheNetwork(t *testing.T) {
	dir := t.TempDir()
	os.MkdirAll(filepath.Join(dir, "meshes"), 0o755)
	os.WriteFile(filepath.Join(dir, "meshes", "broken.obj"), []byte("v 0 0 0\nv 1 0 0\nv 0 1 0\n# a face too far\nf 1 2 7\n"), 0o644)
	path := filepath.Join(dir, "s.json")
	os.WriteFile(path, []byte(`{"shapes": [{"sphere": {"radius": 1}}, {"mesh": {"path": "meshes/broken.obj"}}]}`), 0o644)
	want := "farm: shapes[1].mesh: meshes/broken.obj: line 5: face refers to vertex 7 but the file has 3 vertices\n"
	for _, verb := range [][]string{
		{"submit", path, "--coordinator", closedAddress(t)},
		{"plan", path},
		{"validate", path},
		{"render", path, "--worker-bin", "/bin/true"},
	} {
		code, stdout, stderr := runForTest(t, nil, verb...)
		if code != exitUsage || stderr != want || stdout != "" {
			t.Errorf("%s: exit %d, stdout %q, stderr %q; want exit 2 and %q", verb[0], code, stdout, stderr, want)
		}
	}
}

func TestFailedJobSaysItsFailureKind(t *testing.T) {
	job := &pb.Job{Id: "j-1", State: pb.JobState_JOB_STATE_FAILED, FailureKind: pb.FailureKind_FAILURE_KIND_BAD_INPUT,
		Error: "task j-1.3 failed: shapes[8].mesh: meshes/broken.obj: line 5: face refers to vertex 7 but the file has 3 vertices"}
	const want = "bad input: task j-1.3 failed: shapes[8].mesh: meshes/broken.obj: line 5: face refers to vertex 7 but the file has 3 vertices"
	if err := jobOutcome(job); err == nil || err.Error() != "job j-1 failed: "+want {
		t.Errorf("jobOutcome = %v, want %q", err, "job j-1 failed: "+want)
	}
	var b strings.Builder
	printJob(&b, job, time.Now())
	if !strings.Contains(b.String(), "error     "+want+"\n") {
		t.Errorf("status:\n%s\nlacks the error line %q", b.String(), want)
	}
	// A failure of no stated kind is shown as it is.
	job.FailureKind, job.Error = pb.FailureKind_FAILURE_KIND_UNSPECIFIED, "task j-1.3 failed 3 times; last error: boom"
	if err := jobOutcome(job); err == nil || err.Error() != "job j-1 failed: task j-1.3 failed 3 times; last error: boom" {
		t.Errorf("jobOutcome = %v", err)
	}
}
