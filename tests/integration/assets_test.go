package integration

import (
	"context"
	"encoding/json"
	"os"
	"path/filepath"
	"regexp"
	"strings"
	"syscall"
	"testing"
	"time"

	"google.golang.org/genproto/googleapis/rpc/errdetails"
	"google.golang.org/grpc/codes"
	"google.golang.org/grpc/status"

	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

// brokenMeshScene writes scenes/test-small.json to a folder of its own with its mesh
// replaced by tests/vectors/meshes/refuse-vertex-out-of-range.obj (line 5: face 1 2 7 of
// 3 vertices) as meshes/broken.obj, and returns the scene's path.
func brokenMeshScene(t *testing.T) string {
	t.Helper()
	dir := t.TempDir()
	obj, err := os.ReadFile(filepath.Join(farmtest.RepoRoot(), "tests", "vectors", "meshes", "refuse-vertex-out-of-range.obj"))
	if err != nil {
		t.Fatal(err)
	}
	os.MkdirAll(filepath.Join(dir, "meshes"), 0o755)
	if err := os.WriteFile(filepath.Join(dir, "meshes", "broken.obj"), obj, 0o644); err != nil {
		t.Fatal(err)
	}
	m := smallSceneJSON(t)
	shape(m, 3)["mesh"].(map[string]any)["path"] = "meshes/broken.obj"
	text, _ := json.Marshal(m)
	path := filepath.Join(dir, "broken.json")
	if err := os.WriteFile(path, text, 0o644); err != nil {
		t.Fatal(err)
	}
	return path
}

const brokenMeshLine = "farm: shapes[3].mesh: meshes/broken.obj: line 5: face refers to vertex 7 but the file has 3 vertices"

func TestBrokenMeshStopsSubmitAndRenderWithinFiveSecondsInOneLine(t *testing.T) {
	f := farmtest.StartFarm(t, nil)
	scene := brokenMeshScene(t)
	for _, args := range [][]string{
		{"submit", scene, "--coordinator", f.Addr},
		{"render", scene, "-o", t.TempDir(), "--workers", "1"},
	} {
		start := time.Now()
		code, stdout, stderr := farmtest.RunFarm(t, 5*time.Second, nil, args...)
		took := time.Since(start)
		t.Logf("farm %s: exit %d after %v", args[0], code, took.Round(time.Millisecond))
		if code == 0 || took > 5*time.Second {
			t.Errorf("farm %s: exit %d after %v, want non-zero within 5s", args[0], code, took)
		}
		if stderr != brokenMeshLine+"\n" || stdout != "" {
			t.Errorf("farm %s: stdout %q, stderr %q; want only the line %q", args[0], stdout, stderr, brokenMeshLine)
		}
	}
	if jobs, err := f.Client.ListJobs(context.Background()); err != nil || len(jobs) != 0 {
		t.Errorf("ListJobs = %v, %v; want no job", jobs, err)
	}
}

// TestCoordinatorRefusesABrokenMeshBlob is the same mesh through a client that does not
// check it first: the coordinator process refuses the submit naming the shape, the file
// and the line.
func TestCoordinatorRefusesABrokenMeshBlob(t *testing.T) {
	f := farmtest.StartFarm(t, nil)
	ctx := context.Background()
	sc, err := f.Client.LoadSceneFile(ctx, filepath.Join(farmtest.RepoRoot(), "scenes", "test-small.json"))
	if err != nil {
		t.Fatal(err)
	}
	obj, _ := os.ReadFile(filepath.Join(farmtest.RepoRoot(), "tests", "vectors", "meshes", "refuse-vertex-out-of-range.obj"))
	digest, err := f.Client.UploadBytes(ctx, obj)
	if err != nil {
		t.Fatal(err)
	}
	sc.Shapes[3].GetMesh().Path, sc.Shapes[3].GetMesh().Digest = "meshes/broken.obj", digest
	_, err = f.Client.Jobs().SubmitJob(ctx, &pb.SubmitJobRequest{Scene: sc})
	st := status.Convert(err)
	want := strings.TrimPrefix(brokenMeshLine, "farm: ")
	if st.Code() != codes.InvalidArgument || st.Message() != want {
		t.Fatalf("SubmitJob = %v, want INVALID_ARGUMENT %q", err, want)
	}
	var field string
	for _, d := range st.Details() {
		if br, ok := d.(*errdetails.BadRequest); ok && len(br.GetFieldViolations()) == 1 {
			field = br.GetFieldViolations()[0].GetField()
		}
	}
	if field != "shapes[3].mesh" {
		t.Errorf("field violation names %q, want shapes[3].mesh", field)
	}
}

// TestPermanentFailureFailsTheJobAtOnceAndTheCLISaysWhy has a worker that reports a kind
// (farmtest.FailNextTask) fail a task as bad input: the job fails at that one report,
// and farm status and farm watch say why.
func TestPermanentFailureFailsTheJobAtOnceAndTheCLISaysWhy(t *testing.T) {
	f := farmtest.StartFarm(t, nil)
	job := f.Submit(t, f.TestScene(t, 32, 32, 16, 1))
	const reason = "shapes[3].mesh: OBJ parse error: line 5: face refers to vertex 7 but the file has 3 vertices"
	task := f.FailNextTask(t, "", pb.FailureKind_FAILURE_KIND_BAD_INPUT, reason)
	want := "bad input: task " + task + " failed: " + reason
	code, stdout, _ := farmtest.RunFarm(t, 10*time.Second, nil, "status", job.GetId(), "--coordinator", f.Addr)
	if code != 0 || !regexp.MustCompile(`(?m)^state +failed$`).MatchString(stdout) || !regexp.MustCompile(`(?m)^error +`+regexp.QuoteMeta(want)+`$`).MatchString(stdout) {
		t.Errorf("farm status: exit %d\n%s\nwant the job failed with %q", code, stdout, want)
	}
	code, _, stderr := farmtest.RunFarm(t, 10*time.Second, nil, "watch", job.GetId(), "--coordinator", f.Addr)
	if code != 1 || stderr != "farm: job "+job.GetId()+" failed: "+want+"\n" {
		t.Errorf("farm watch: exit %d, stderr %q; want 1 and the job's reason", code, stderr)
	}
}

// TestSubmitStopsAtSIGTERMWhileReadingALargeMesh: farm submit reading a large file (the
// largest a mesh may be, sparse) stops at SIGTERM instead of reading on.
func TestSubmitStopsAtSIGTERMWhileReadingALargeMesh(t *testing.T) {
	dir := t.TempDir()
	big := filepath.Join(dir, "big.obj")
	fh, err := os.Create(big)
	if err != nil {
		t.Fatal(err)
	}
	fh.Truncate(int64(rules.Scene.GetMaxAssetBytes())) // at the size limit, so it is read
	fh.Close()
	os.WriteFile(filepath.Join(dir, "s.json"), []byte(`{"shapes": [{"mesh": {"path": "big.obj"}}]}`), 0o644)
	cmd, _, stderr, _ := farmCommand(t, "submit", filepath.Join(dir, "s.json"), "--coordinator", farmtest.ClosedAddress(t))
	time.Sleep(300 * time.Millisecond)
	start := time.Now()
	syscall.Kill(cmd.Process.Pid, syscall.SIGTERM)
	code := waitTimeout(t, cmd, 5*time.Second)
	t.Logf("farm submit stopped %v after SIGTERM, exit %d: %s", time.Since(start).Round(time.Millisecond), code, strings.TrimSpace(stderr.String()))
	if code != 130 || time.Since(start) > 2*time.Second {
		t.Errorf("farm submit after SIGTERM: exit %d after %v, want 130 within 2s; stderr %q", code, time.Since(start), stderr)
	}
}

// TestRealWorkerFailsABadReferenceAsBadInputAtTheFirstReport: a reference image whose
// OpenEXR header is sound (the film's size: submit checks only the header) but which holds
// no pixels reaches a real farm-worker's composite, which fails the task as bad input; the
// job fails at that one report with the reason, and no worker is blamed.
func TestRealWorkerFailsABadReferenceAsBadInputAtTheFirstReport(t *testing.T) {
	f := farmtest.StartFarm(t, nil)
	f.StartWorker(t)
	f.StartWorker(t)
	ctx := context.Background()
	digest, err := f.Client.UploadBytes(ctx, testEXR(false, exrPixelFloat, 16, 16, 16))
	if err != nil {
		t.Fatal(err)
	}
	sc := f.TestScene(t, 16, 16, 16, 1)
	sc.Progressive = &pb.Progressive{Reference: &pb.ReferenceImage{Digest: digest}}
	job := f.Submit(t, sc)
	wctx, cancel := context.WithTimeout(ctx, 60*time.Second)
	defer cancel()
	end, err := f.Client.Watch(wctx, job.GetId(), nil)
	if err != nil {
		t.Fatal(err)
	}
	const reason = "progressive.reference.digest: reference image is not a readable OpenEXR file"
	if end.GetState() != pb.JobState_JOB_STATE_FAILED || end.GetFailureKind() != pb.FailureKind_FAILURE_KIND_BAD_INPUT ||
		!strings.Contains(end.GetError(), reason) {
		t.Fatalf("job ended %v (%v): %q; want FAILED as bad input naming %q", end.GetState(), end.GetFailureKind(), end.GetError(), reason)
	}
	if len(end.GetBlockedWorkers()) != 0 {
		t.Errorf("blocked workers %v, want none: bad input is no worker's fault", end.GetBlockedWorkers())
	}
	composite := farmtest.TasksOf(f.Tasks(t, job.GetId()), pb.Phase_PHASE_COMPOSITE)
	if len(composite) != 1 || composite[0].GetAttempts() != 1 || composite[0].GetFailureKind() != pb.FailureKind_FAILURE_KIND_BAD_INPUT {
		t.Errorf("composite tasks %v, want one that failed as bad input at its first attempt", composite)
	}
}
