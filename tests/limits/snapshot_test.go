package limits

import (
	"fmt"
	"strings"
	"testing"
	"time"

	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

// snapshotMargin is how much more than the largest snapshot any process of the farm may
// hold at its peak: the coordinator's build holds 24 bytes a photon (the snapshot with
// irradiance is 24 bytes a global photon) and a worker maps the snapshot, each beside a
// runtime, a scene and buffers of well under this. Holding the snapshot twice anywhere
// (an output beside its working records, a download in memory beside the mapped file)
// would pass it at the limit.
const snapshotMargin = 512 << 20

// TestSnapshotAtThePhotonCapRenders renders a furnace whose snapshot holds nearly the most
// photons a snapshot may (max_snapshot_photons, all global, with irradiance: the largest
// snapshot there is; reduced: 100,000 paths) on two workers with caches of their own, so
// that each fetches both of the round's snapshots (before and after the irradiance merge)
// in ranges (64 MiB; reduced: 1 MiB). It logs each phase's time and each process's peak
// memory, and fails if any process peaked above the merged snapshot's size plus
// snapshotMargin: no process held the snapshot twice. With -limits.full, a furnace over
// the cap must then fail as bad input saying what to lower.
func TestSnapshotAtThePhotonCapRenders(t *testing.T) {
	limit := rules.Scene.GetMaxSnapshotPhotons()
	paths := size(limit/4*39/40, uint64(100_000)) // 2.5% under, about 60 standard deviations
	workerFlags := []string{"--threads", "1", "--download-range-bytes", size("64M", "1M")}
	r := newRunOf(t, workerFlags, workerFlags)
	sc := farmtest.Furnace(paths)
	sc.Photons.PhotonsPerShard = size(uint64(100_000), 25_000) // reduced: 4 shards, so both workers fetch
	job := r.render(sc, 3*time.Hour)
	var photons, snapshot uint64
	for _, task := range r.f.Tasks(t, job.GetId()) {
		if task.GetPhase() == pb.Phase_PHASE_BUILD || task.GetPhase() == pb.Phase_PHASE_MERGE {
			a := task.GetOutputs()[0]
			t.Logf("  %s snapshot: %d bytes (%s)", task.GetPhase(), a.GetSizeBytes(), mb(uint64(a.GetSizeBytes())))
			if task.GetPhase() == pb.Phase_PHASE_BUILD {
				photons = (uint64(a.GetSizeBytes()) - 128) / 20 // one map: header, directory entry, 20 bytes a photon
			} else {
				snapshot = uint64(a.GetSizeBytes())
			}
		}
	}
	peak := r.f.Coordinator().PeakRSS(t)
	t.Logf("%d paths stored %d photons (cap %d); coordinator peak %s, %.1f bytes a photon", paths, photons, limit, mb(peak), float64(peak)/float64(photons))
	if photons > limit {
		t.Errorf("%d photons stored, over the cap %d: choose fewer paths", photons, limit)
	}
	procs := append([]*farmtest.Proc{r.f.Coordinator()}, r.workers...)
	for _, p := range procs {
		if peak := p.PeakRSS(t); peak > snapshot+snapshotMargin {
			t.Errorf("%s peaked at %s, more than the snapshot's %s and %s: it held the snapshot twice", p.Name, mb(peak), mb(snapshot), mb(snapshotMargin))
		}
	}
	r.taskTimes()
	if !*full {
		return
	}
	over := r.f.Submit(t, farmtest.Furnace(limit/4*41/40))
	ended, err := r.f.Client.Watch(ctx(t, time.Hour), over.GetId(), nil)
	if err != nil {
		t.Fatal(err)
	}
	want := fmt.Sprintf("more than the %d photons a snapshot may hold (scene_limits.max_snapshot_photons)", limit)
	if ended.GetState() != pb.JobState_JOB_STATE_FAILED || ended.GetFailureKind() != pb.FailureKind_FAILURE_KIND_BAD_INPUT ||
		!strings.Contains(ended.GetError(), want) || !strings.Contains(ended.GetError(), "lower photons.global_photons") {
		t.Errorf("a furnace over the cap: %v %v %q, want it failed as bad input naming the limit", ended.GetState(), ended.GetFailureKind(), ended.GetError())
	}
	t.Logf("over the cap: %s; coordinator peak since start %s", ended.GetError(), mb(r.f.Coordinator().PeakRSS(t)))
}
