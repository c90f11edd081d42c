// Package dashboard_test runs the dashboard's browser test (issue 6's acceptance): a real
// farm with tokens (a coordinator, two workers), `farm dashboard` in front of it, and
// e2e/dashboard.spec.mjs driving Debian's chromium through playwright-core against it.
package dashboard_test

import (
	"bytes"
	"context"
	"encoding/binary"
	"os"
	"os/exec"
	"path/filepath"
	"strings"
	"testing"
	"time"

	"photonfarm/client"
	"photonfarm/contract/scene/scenetest"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"

	"google.golang.org/grpc"
	"google.golang.org/grpc/credentials/insecure"
)

const (
	clientToken = "dashboard-client-token-for-the-test"
	workerToken = "dashboard-worker-token-for-the-test"
	chromium    = "/usr/bin/chromium"
)

// TestDashboardInABrowser logs in, submits a scene through the file input, watches its
// progress and tiles arrive, sees the final image and both workers, saves a screenshot of
// the job page, cancels a long job, retries, requeues and deletes jobs: every step is in e2e/dashboard.spec.mjs, which
// prints one line per step.
func TestDashboardInABrowser(t *testing.T) {
	e2e := filepath.Join(farmtest.RepoRoot(), "tests", "dashboard", "e2e")
	node := browserTools(t, e2e)

	f := farmtest.StartFarm(t, farmtest.TokenFlags(t, clientToken, workerToken), client.WithToken(clientToken))
	// Before the workers start, so that no real worker leases its task first.
	failedJob := failAsBadInput(t, f)
	requeueJob := failAsBadInput(t, f) // the first has failed, so its task is this one's
	for range 2 {
		w := f.StartWorker(t, "--token", workerToken)
		if w.WorkerID(t, 15*time.Second) == "" {
			t.Fatalf("%s did not register within 15 s", w.Name)
		}
	}
	workerFailedJob := failOnARealWorker(t, f)
	blockedJob, blockedWorker := blockAWorker(t, f)
	_, url := f.StartDashboard(t)

	shots := os.Getenv("DASHBOARD_SCREENSHOT_DIR")
	if shots == "" {
		shots = t.TempDir()
	} else if abs, err := filepath.Abs(shots); err == nil {
		shots = abs
	}
	t.Logf("dashboard %s; screenshots go to %s", url, shots)

	ctx, cancel := context.WithTimeout(context.Background(), 8*time.Minute)
	defer cancel()
	cmd := exec.CommandContext(ctx, node, "dashboard.spec.mjs")
	cmd.Dir = e2e
	cmd.Env = append(os.Environ(),
		"DASHBOARD_URL="+url,
		"FARM_TOKEN="+clientToken,
		"SCENE_PATH="+filepath.Join(e2e, "scene.json"),
		"SCREENSHOT_DIR="+shots,
		"CHROMIUM="+chromium,
		"FAILED_JOB_ID="+failedJob,
		"FAILED_REASON="+badInputReason,
		"WORKER_FAILED_JOB_ID="+workerFailedJob,
		"WORKER_FAILED_REASON="+badReferenceReason,
		"REQUEUE_JOB_ID="+requeueJob,
		"BLOCKED_JOB_ID="+blockedJob,
		"BLOCKED_WORKER_ID="+blockedWorker,
		"PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1",
	)
	var out bytes.Buffer
	cmd.Stdout, cmd.Stderr = &out, &out
	err := cmd.Run()
	if ctx.Err() != nil {
		t.Fatalf("dashboard.spec.mjs did not finish within 8 minutes; its output:\n%s", out.String())
	}
	if err != nil {
		t.Fatalf("dashboard.spec.mjs failed (%v); its output:\n%s", err, out.String())
	}
	t.Logf("dashboard.spec.mjs:\n%s", out.String())
	t.Logf("job page screenshot: %s", filepath.Join(shots, "job-page.png"))
}

// badInputReason is what failAsBadInput's worker reports.
const badInputReason = "shapes[3].mesh: line 5: face refers to vertex 7 but the file has 3 vertices"

// failAsBadInput submits a small scene whose first task a worker fails as bad input
// (farmtest.FailNextTask), which fails the job at once, and returns the job's id.
func failAsBadInput(t *testing.T, f *farmtest.Farm) string {
	t.Helper()
	job := f.Submit(t, f.TestScene(t, 32, 32, 16, 1))
	f.FailNextTask(t, workerToken, pb.FailureKind_FAILURE_KIND_BAD_INPUT, badInputReason)
	if got, err := f.Client.GetJob(context.Background(), job.GetId()); err != nil || got.GetState() != pb.JobState_JOB_STATE_FAILED {
		t.Fatalf("job after the bad-input report: %v, %v; want it failed", got, err)
	}
	return job.GetId()
}

// badReferenceReason is what a real worker's composite reports for the reference image
// that failOnARealWorker's job names.
const badReferenceReason = "progressive.reference.digest: reference image is not a readable OpenEXR file"

// failOnARealWorker submits a small scene whose reference image is an OpenEXR header
// without pixels (the film's size: submit checks only the header): a real farm-worker's
// composite fails it as bad input, and the job fails at that report with the task's log.
// It returns the job's id once the job has failed so.
func failOnARealWorker(t *testing.T, f *farmtest.Farm) string {
	t.Helper()
	ctx, cancel := context.WithTimeout(context.Background(), 60*time.Second)
	defer cancel()
	digest, err := f.Client.UploadBytes(ctx, exrHeaderOnly(16, 16))
	if err != nil {
		t.Fatal(err)
	}
	sc := f.TestScene(t, 16, 16, 16, 1)
	sc.Name = "bad-reference-job"
	sc.Progressive = &pb.Progressive{Reference: &pb.ReferenceImage{Digest: digest}}
	job := f.Submit(t, sc)
	end, err := f.Client.Watch(ctx, job.GetId(), nil)
	if err != nil || end.GetState() != pb.JobState_JOB_STATE_FAILED || !strings.Contains(end.GetError(), badReferenceReason) {
		t.Fatalf("the job with a reference image without pixels ended %v (%v): %q; want FAILED naming %q",
			end.GetState(), err, end.GetError(), badReferenceReason)
	}
	return job.GetId()
}

// exrHeaderOnly is a scanline OpenEXR file of w x h float RGBA pixels that ends after its
// header: no offset table, no pixels.
func exrHeaderOnly(w, h int32) []byte {
	le := binary.LittleEndian
	attr := func(b []byte, name, typ string, value []byte) []byte {
		b = append(append(append(append(b, name...), 0), typ...), 0)
		return append(le.AppendUint32(b, uint32(len(value))), value...)
	}
	var channels []byte
	for _, c := range []string{"A", "B", "G", "R"} { // sorted, as OpenEXR stores them
		channels = append(append(channels, c...), 0)
		channels = le.AppendUint32(channels, 2) // FLOAT
		channels = append(channels, 0, 0, 0, 0) // pLinear and reserved
		channels = le.AppendUint32(le.AppendUint32(channels, 1), 1)
	}
	var window []byte
	for _, v := range []int32{0, 0, w - 1, h - 1} {
		window = le.AppendUint32(window, uint32(v))
	}
	b := le.AppendUint32(le.AppendUint32(nil, 20000630), 2) // magic, version 2 (scanline)
	b = attr(b, "channels", "chlist", append(channels, 0))
	b = attr(b, "compression", "compression", []byte{3}) // ZIP
	b = attr(b, "dataWindow", "box2i", window)
	b = attr(b, "displayWindow", "box2i", window)
	return append(b, 0)
}

// blockAWorker submits a long job of low priority (render tiles only, far too many to
// finish during the test, so the real workers run it only when nothing else is queued),
// blocks a worker from it the way the coordinator does (three failed attempts; the real
// workers are live, so the job does not fail for want of a worker), unregisters that
// worker, and returns the job's and the worker's ids.
func blockAWorker(t *testing.T, f *farmtest.Farm) (jobID, workerID string) {
	t.Helper()
	sc := scenetest.Unlit(1280, 960)
	sc.Name = "blocked-worker-job"
	sc.Sampling.SamplesPerPixel = 512
	ctx, cancel := context.WithTimeout(context.Background(), 30*time.Second)
	defer cancel()
	job, err := f.Client.Submit(ctx, sc, client.WithPriority(-10))
	if err != nil {
		t.Fatal(err)
	}
	conn, err := grpc.NewClient(f.Addr, grpc.WithTransportCredentials(insecure.NewCredentials()), client.WorkerSecrets())
	if err != nil {
		t.Fatal(err)
	}
	defer conn.Close()
	wctx := client.ContextWithToken(ctx, workerToken)
	w := pb.NewWorkerServiceClient(conn)
	reg, err := w.RegisterWorker(wctx, &pb.RegisterWorkerRequest{Hostname: "flaky-worker"})
	if err != nil {
		t.Fatal(err)
	}
	for i := range 3 {
		l, err := w.LeaseTask(wctx, &pb.LeaseTaskRequest{WorkerId: reg.GetWorkerId()})
		if err != nil || l.GetLease() == nil {
			t.Fatalf("lease %d of the flaky worker: %v, %v; want a task", i, l, err)
		}
		if _, err := w.FailTask(wctx, &pb.FailTaskRequest{WorkerId: reg.GetWorkerId(), TaskId: l.GetLease().GetTaskId(),
			Epoch: l.GetLease().GetEpoch(), Error: "out of memory"}); err != nil {
			t.Fatal(err)
		}
	}
	if _, err := w.UnregisterWorker(wctx, &pb.UnregisterWorkerRequest{WorkerId: reg.GetWorkerId()}); err != nil {
		t.Fatal(err)
	}
	got, err := f.Client.GetJob(ctx, job.GetId())
	if err != nil || len(got.GetBlockedWorkers()) != 1 || got.GetState() != pb.JobState_JOB_STATE_RUNNING && got.GetState() != pb.JobState_JOB_STATE_QUEUED {
		t.Fatalf("the job after three failures of one worker: %v, %v; want it running with that worker blocked", got, err)
	}
	return job.GetId(), reg.GetWorkerId()
}

// browserTools checks that node, chromium and the pinned playwright-core are installed and
// returns node's path. Missing, the test fails (never skips) saying how to install them.
func browserTools(t *testing.T, e2e string) string {
	t.Helper()
	const fix = "; run scripts/install-deps.sh (it installs Debian's chromium, node and npm, and runs npm ci in tests/dashboard/e2e)"
	node, err := exec.LookPath("node")
	if err != nil {
		t.Fatal("node is not on PATH" + fix)
	}
	if _, err := os.Stat(chromium); err != nil {
		t.Fatalf("%s: %v%s", chromium, err, fix)
	}
	if _, err := os.Stat(filepath.Join(e2e, "node_modules", "playwright-core", "package.json")); err != nil {
		t.Fatalf("playwright-core is not installed in tests/dashboard/e2e/node_modules%s", fix)
	}
	return node
}
