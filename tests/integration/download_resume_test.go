package integration

import (
	"os"
	"path/filepath"
	"regexp"
	"strconv"
	"testing"
	"time"

	"photonfarm/coordinator/blobstore"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
	"photonfarm/tests/tcpproxy"
)

// A worker fetches a photon snapshot of about 24 MB in ranges of 16 MiB, through a proxy
// (tcpproxy) that cuts every connection once, 8 MiB into the snapshot (in its first range): the
// worker resumes the download where the bytes stopped (it says so, naming the byte), the
// job completes, and the proxy forwarded far fewer bytes than a download (or a range)
// started over would take.
func TestACutSnapshotDownloadResumesWhereItStopped(t *testing.T) {
	f := farmtest.StartFarm(t, nil)
	sc := farmtest.Furnace(300_000) // about 1.2M photons: a snapshot of about 24 MB
	// The global map seen directly: one snapshot, no precompute over its photons.
	sc.Indirect = &pb.Indirect{Mode: pb.IndirectMode_INDIRECT_MODE_PHOTON_MAP}
	job := f.Submit(t, sc)

	// The snapshot comes first, with nothing but small messages before it: shards and
	// tiles go up, not down.
	proxy := tcpproxy.New(t, f.Addr)
	const cutAt = 8 << 20
	cut := proxy.CutOnceAfter(cutAt)
	w := f.StartWorkerVia(t, proxy.Addr, t.TempDir(), "--download-range-bytes", "16M")
	done := f.Wait(t, job.GetId(), 3*time.Minute)
	if done.GetState() != pb.JobState_JOB_STATE_SUCCEEDED {
		t.Fatalf("job %v: %s", done.GetState(), done.GetError())
	}
	select {
	case <-cut:
	default:
		t.Fatalf("the proxy never cut: it forwarded %d bytes in all", proxy.Downstream())
	}
	var size int64
	for _, task := range farmtest.TasksOf(f.Tasks(t, job.GetId()), pb.Phase_PHASE_BUILD) {
		size = task.GetOutputs()[0].GetSizeBytes()
	}
	if size < 2*cutAt {
		t.Fatalf("the snapshot has %d bytes; the test needs more than twice the cut's %d", size, cutAt)
	}
	m := regexp.MustCompile(`msg="download cut; resuming" .*at=(\d+) of=(\d+)`).FindStringSubmatch(w.LogTail(1000))
	if m == nil {
		t.Fatalf("the worker never said it resumed a download; its log:\n%s", w.LogTail(40))
	}
	at, _ := strconv.ParseInt(m[1], 10, 64)
	if of, _ := strconv.ParseInt(m[2], 10, 64); of != size || at <= 0 || at >= size {
		t.Errorf("resumed at byte %d of %d; want inside the snapshot of %d bytes", at, of, size)
	}
	// Starting over, the download or its range, would forward the cut's 8 MiB again; what
	// is lost at a cut is what was in flight (a few flow-control windows).
	if wasted := proxy.Downstream() - size; wasted > cutAt/2 {
		t.Errorf("the proxy forwarded %d bytes for a snapshot of %d: %d more, as if the download started over", proxy.Downstream(), size, wasted)
	}
	t.Logf("snapshot %d bytes, cut at %d forwarded bytes, resumed at byte %d; %d bytes forwarded in all", size, int64(cutAt), at, proxy.Downstream())
}

// A range is sent as stored, unchecked: a snapshot damaged in the coordinator's store after
// its build reaches the worker in ranges, and the worker, finding that the whole does not
// match its digest, asks GetBlobInfo, which finds the damage: the job fails at once as
// lost input naming the snapshot, and no worker is blamed. The worker is held behind a
// frozen proxy from the end of the emission to the damage, so it cannot fetch the snapshot
// before it is damaged.
func TestASnapshotDamagedInTheStoreFetchedInRangesIsLostInput(t *testing.T) {
	f, blobs := lostInputFarm(t)
	sc := farmtest.Furnace(100_000)
	sc.Indirect = &pb.Indirect{Mode: pb.IndirectMode_INDIRECT_MODE_PHOTON_MAP}
	job := f.Submit(t, sc)
	proxy := tcpproxy.New(t, f.Addr)
	cache := t.TempDir()
	f.StartWorkerVia(t, proxy.Addr, cache, "--download-range-bytes", "1M")
	phaseDone := func(phase pb.Phase) []*pb.Task {
		for deadline := time.Now().Add(2 * time.Minute); time.Now().Before(deadline); time.Sleep(5 * time.Millisecond) {
			tasks := farmtest.TasksOf(f.Tasks(t, job.GetId()), phase)
			done := len(tasks) > 0
			for _, task := range tasks {
				done = done && task.GetState() == pb.TaskState_TASK_STATE_SUCCEEDED
			}
			if done {
				return tasks
			}
		}
		t.Fatalf("the %v phase did not finish within 2 minutes", phase)
		return nil
	}
	phaseDone(pb.Phase_PHASE_EMIT)
	proxy.Freeze()
	snap := phaseDone(pb.Phase_PHASE_BUILD)[0].GetOutputs()[0].GetDigest()
	if _, err := os.Stat(filepath.Join(cache, "sha256", snap[len("sha256:"):])); err == nil {
		t.Fatal("the worker fetched the snapshot before the proxy froze (the build took less than the test's poll)")
	}
	path := blobstore.PathIn(blobs, snap)
	data, err := os.ReadFile(path)
	if err != nil {
		t.Fatal(err)
	}
	data[len(data)/2] ^= 0x10 // a photon's coordinate: the file still parses
	if err := os.WriteFile(path, data, 0o644); err != nil {
		t.Fatal(err)
	}
	start := time.Now()
	proxy.Thaw()
	waitLostInput(t, f, job.GetId(), "the photon snapshot of round 1: blob "+snap+" is damaged in the coordinator's blob store", start, 30*time.Second)
}
