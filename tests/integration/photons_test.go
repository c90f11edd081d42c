package integration

import (
	"bytes"
	"path/filepath"
	"testing"
	"time"

	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

// causticsFile is scenes/test-caustics.json: the Cornell box with a mirror and a glass
// sphere under a quad light, 64x64 in 16 tiles of 16, with a global and a caustic map of
// 40,000 photon paths each in shards of 10,000 (8 emission shards, tens of milliseconds
// each on one thread).
const causticsFile = "test-caustics.json"

// slowShards makes each emission shard of the caustics scene take a few hundred
// milliseconds (100,000 paths), so that a kill lands while a shard is leased.
func slowShards(sc *pb.Scene) *pb.Scene {
	sc.Photons.GlobalPhotons, sc.Photons.CausticPhotons, sc.Photons.PhotonsPerShard = 400000, 400000, 100000
	return sc
}

var causticsSize = sceneSize{width: 64, height: 64, tile: 16}

// checkCausticsOutputs checks the final EXR (with its AOV layers) and the preview, and
// returns the EXR.
func checkCausticsOutputs(t *testing.T, f *farmtest.Farm, job *pb.Job) []byte {
	t.Helper()
	s := causticsSize
	exr := f.Output(t, job, "image.exr")
	if err := checkFinalEXR(exr, int(s.width), int(s.height), int(s.tile), aovChannels...); err != nil {
		t.Error(err)
	}
	w, h, err := pngSize(f.Output(t, job, "preview.png"))
	if err != nil || w != int(s.width) || h != int(s.height) {
		t.Errorf("preview.png: %dx%d, %v; want %dx%d", w, h, err, s.width, s.height)
	}
	return exr
}

// checkPhotonPlan checks that the job went through emit (8 shards of perShard paths,
// global map first), build (by the coordinator), irradiance precompute (one task per
// global shard), merge (by the coordinator) and render, and every task succeeded.
func checkPhotonPlan(t *testing.T, tasks []*pb.Task, perShard uint64) {
	t.Helper()
	emit, build := farmtest.TasksOf(tasks, pb.Phase_PHASE_EMIT), farmtest.TasksOf(tasks, pb.Phase_PHASE_BUILD)
	pre, merge := farmtest.TasksOf(tasks, pb.Phase_PHASE_PRECOMPUTE), farmtest.TasksOf(tasks, pb.Phase_PHASE_MERGE)
	if len(emit) != 8 || len(build) != 1 || len(pre) != 4 || len(merge) != 1 || len(farmtest.TasksOf(tasks, pb.Phase_PHASE_RENDER)) != 16 {
		t.Fatalf("%d emit, %d build, %d precompute, %d merge, %d render tasks; want 8, 1, 4, 1 and 16",
			len(emit), len(build), len(pre), len(merge), len(farmtest.TasksOf(tasks, pb.Phase_PHASE_RENDER)))
	}
	if m := merge[0]; m.GetWorkerId() != "coordinator-builder" || len(m.GetOutputs()) != 1 || m.GetOutputs()[0].GetName() != "photons.snapshot" {
		t.Errorf("merge task = %v, want it done by the coordinator with a photons.snapshot", m)
	}
	for i, e := range emit {
		wantMap := pb.PhotonMapKind_PHOTON_MAP_KIND_GLOBAL
		if i >= 4 {
			wantMap = pb.PhotonMapKind_PHOTON_MAP_KIND_CAUSTIC
		}
		if spec := e.GetEmitPhotons(); spec.GetMap() != wantMap || spec.GetFirstPhoton() != perShard*uint64(i%4) {
			t.Errorf("emit task %d = %v", i, spec)
		}
	}
	checkAllSucceeded(t, tasks)
	if b := build[0]; b.GetWorkerId() != "coordinator-builder" || len(b.GetOutputs()) != 1 || b.GetOutputs()[0].GetName() != "photons.snapshot" {
		t.Errorf("build task = %v, want it done by the coordinator with a photons.snapshot", b)
	}
}

func TestCausticsTwoWorkersBitIdenticalToOneWorker(t *testing.T) {
	two := farmtest.StartFarm(t, nil)
	cache := filepath.Join(t.TempDir(), "shared-cache") // two workers on one host share it
	w1, w2 := two.StartWorkerWithCache(t, cache), two.StartWorkerWithCache(t, cache)
	w1.WorkerID(t, 15*time.Second)
	w2.WorkerID(t, 15*time.Second)
	job := two.Render(t, two.LoadScene(t, causticsFile), 120*time.Second)
	exrTwo := checkCausticsOutputs(t, two, job)

	tasks := two.Tasks(t, job.GetId())
	checkPhotonPlan(t, tasks, 10000)
	checkBothWorkers(t, tasks, pb.Phase_PHASE_EMIT)

	one := farmtest.StartFarm(t, nil)
	one.StartWorker(t)
	jobOne := one.Render(t, one.LoadScene(t, causticsFile), 120*time.Second)
	exrOne := checkCausticsOutputs(t, one, jobOne)
	if !bytes.Equal(farmtest.WithoutRenderTime(exrTwo), farmtest.WithoutRenderTime(exrOne)) {
		t.Errorf("EXR from two workers (%d bytes) differs from the one from one worker (%d bytes)", len(exrTwo), len(exrOne))
	}
}

func TestWorkerKilledDuringEmissionLeaseExpiresAndImageIsUnchanged(t *testing.T) {
	f := farmtest.StartFarm(t, nil)
	first := f.StartWorker(t)
	first.WorkerID(t, 15*time.Second)
	sc := slowShards(f.LoadScene(t, causticsFile))
	job := f.Submit(t, sc)

	victim := killWhileLeasing(t, f, first, job.GetId(), pb.Phase_PHASE_EMIT)

	second := f.StartWorker(t)
	secondID := second.WorkerID(t, 15*time.Second)
	done := f.Wait(t, job.GetId(), 120*time.Second)
	exrAfterKill := checkCausticsOutputs(t, f, done)
	tasks := f.Tasks(t, job.GetId())
	checkPhotonPlan(t, tasks, 100000)
	checkTakenOver(t, tasks, victim, secondID)
	checkSameAsUndisturbed(t, f, sc, exrAfterKill, 120*time.Second)
}

// TestSpectralCausticsBitIdenticalWithOneOrTwoWorkersAndAfterAKill: the caustics scene
// with its glass ball made of BK7, traced in spectral mode (every photon and camera path at
// eight wavelengths, the hero alone past the glass), renders to the same bytes on two
// workers as on one, also when the only worker is SIGKILLed during emission and another
// takes over (issue 18, acceptance 4).
func TestSpectralCausticsBitIdenticalWithOneOrTwoWorkersAndAfterAKill(t *testing.T) {
	dispersive := func(f *farmtest.Farm) *pb.Scene {
		sc := slowShards(f.LoadScene(t, causticsFile))
		for _, m := range sc.GetMaterials() {
			if d := m.GetDielectric(); d != nil {
				d.Ior = 1.5168
				d.Dispersion = &pb.Dispersion{Law: &pb.Dispersion_Glass{Glass: pb.Glass_GLASS_BK7}}
			}
		}
		if sc.Sampling == nil {
			sc.Sampling = &pb.Sampling{}
		}
		sc.Sampling.Spectral = pb.SpectralSampling_SPECTRAL_SAMPLING_ALWAYS
		return sc
	}
	two := farmtest.StartFarm(t, nil)
	two.StartWorker(t)
	two.StartWorker(t)
	exrTwo := checkCausticsOutputs(t, two, two.Render(t, dispersive(two), 180*time.Second))

	f := farmtest.StartFarm(t, nil)
	first := f.StartWorker(t)
	first.WorkerID(t, 15*time.Second)
	sc := dispersive(f)
	job := f.Submit(t, sc)
	if !planRuns(job, "dispersion") {
		t.Errorf("the plan does not run dispersion: %v", job.GetPlan())
	}
	victim := killWhileLeasing(t, f, first, job.GetId(), pb.Phase_PHASE_EMIT)
	second := f.StartWorker(t)
	secondID := second.WorkerID(t, 15*time.Second)
	exrAfterKill := checkCausticsOutputs(t, f, f.Wait(t, job.GetId(), 180*time.Second))
	checkTakenOver(t, f.Tasks(t, job.GetId()), victim, secondID)
	if !bytes.Equal(farmtest.WithoutRenderTime(exrTwo), farmtest.WithoutRenderTime(exrAfterKill)) {
		t.Errorf("the spectral render on two workers (%d bytes) differs from the one after a kill (%d bytes)", len(exrTwo), len(exrAfterKill))
	}
	// And the same again on the one worker left, undisturbed.
	checkSameAsUndisturbed(t, f, sc, exrAfterKill, 180*time.Second)
}

// planRuns says whether job's plan runs the pass called name.
func planRuns(job *pb.Job, name string) bool {
	for _, p := range job.GetPlan().GetPasses() {
		if p.GetName() == name {
			return p.GetEnabled()
		}
	}
	return false
}
