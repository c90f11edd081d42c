package integration

import (
	"bytes"
	"slices"
	"strings"
	"syscall"
	"testing"
	"time"

	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

// adaptiveCaustics is progressiveCaustics over 4 rounds with adaptive sampling on and two
// samples a pixel, so that rounds 3 and 4 draw by the sample maps of rounds 2 and 3.
func adaptiveCaustics(t *testing.T, f *farmtest.Farm) *pb.Scene {
	sc := progressiveCaustics(t, f, 4, 0)
	sc.Sampling.SamplesPerPixel = 2
	sc.Sampling.Adaptive = pb.AdaptiveSampling_ADAPTIVE_SAMPLING_ON
	return sc
}

// checkAdaptiveJob checks that the composites of rounds 2 and 3 made sample maps, the
// job's outputs leave them out, the EXR has the samples layer, and the last round reports
// where the samples went; it returns the EXR.
func checkAdaptiveJob(t *testing.T, f *farmtest.Farm, job *pb.Job) []byte {
	t.Helper()
	for _, c := range farmtest.TasksOf(f.Tasks(t, job.GetId()), pb.Phase_PHASE_COMPOSITE) {
		made := slices.ContainsFunc(c.GetOutputs(), func(a *pb.Artifact) bool { return a.GetName() == "samples.map" })
		if want := c.GetRound() >= 2; made != want {
			t.Errorf("composite of round %d made a sample map: %v, want %v", c.GetRound(), made, want)
		}
	}
	for _, a := range job.GetOutputs() {
		if a.GetName() == "samples.map" {
			t.Errorf("the job's outputs include a sample map: %v", job.GetOutputs())
		}
	}
	exr := f.Output(t, job, "image.exr")
	if err := checkFinalEXR(exr, 32, 32, 16, append(slices.Clone(aovChannels), "samples.Y")...); err != nil {
		t.Error(err)
	}
	rounds := job.GetRounds()
	sp := rounds[len(rounds)-1].GetSamples()
	if sp.GetLayer() != "samples.Y" || sp.GetMin() < 4 || sp.GetMax() <= sp.GetMin() || sp.TopErrorDecileShare == nil {
		t.Errorf("round %d's samples = %v, want layer samples.Y, at least 4 a pixel (one a round), a spread and a top-decile share", len(rounds), sp)
	}
	return exr
}

// Adaptive sampling keeps the farm's determinism: the allocation is a pure function of the
// stored accumulation, so two workers, one worker, and a worker killed while it renders a
// tile of an adaptive round all make the same bytes.
func TestAdaptiveRoundsBitIdenticalWithTwoWorkersOneAndAKill(t *testing.T) {
	two := farmtest.StartFarm(t, nil)
	two.StartWorker(t)
	two.StartWorker(t)
	jobTwo := two.Render(t, adaptiveCaustics(t, two), 180*time.Second)
	exrTwo := checkAdaptiveJob(t, two, jobTwo)
	code, stdout, stderr := farmtest.RunFarm(t, 30*time.Second, nil, "report", jobTwo.GetId(), "--coordinator", two.Addr)
	if code != 0 || !strings.Contains(stdout, "samples after round 4 (layer samples.Y of the EXR)") || !strings.Contains(stdout, "largest estimated error drew") {
		t.Errorf("farm report: exit %d, stderr %s, stdout:\n%s\nwant where the samples went", code, stderr, stdout)
	}
	t.Logf("farm report:\n%s", stdout)

	one := farmtest.StartFarm(t, nil)
	first := one.StartWorker(t)
	first.WorkerID(t, 15*time.Second)
	exrOne := checkAdaptiveJob(t, one, one.Render(t, adaptiveCaustics(t, one), 180*time.Second))
	if !bytes.Equal(farmtest.WithoutRenderTime(exrTwo), farmtest.WithoutRenderTime(exrOne)) {
		t.Errorf("EXR from two workers (%d bytes) differs from the one from one worker (%d bytes)", len(exrTwo), len(exrOne))
	}

	job := one.Submit(t, adaptiveCaustics(t, one))
	for deadline := time.Now().Add(120 * time.Second); ; time.Sleep(5 * time.Millisecond) {
		if time.Now().After(deadline) {
			t.Fatalf("no render tile of round 3 or later was leased within 120s")
		}
		leased := slices.ContainsFunc(farmtest.TasksOf(one.Tasks(t, job.GetId()), pb.Phase_PHASE_RENDER), func(task *pb.Task) bool {
			return task.GetRound() >= 3 && task.GetState() == pb.TaskState_TASK_STATE_LEASED
		})
		if leased {
			break
		}
	}
	first.Kill(syscall.SIGKILL)
	<-first.Done()
	one.StartWorker(t)
	exrKill := checkAdaptiveJob(t, one, one.Wait(t, job.GetId(), 180*time.Second))
	if !bytes.Equal(farmtest.WithoutRenderTime(exrKill), farmtest.WithoutRenderTime(exrOne)) {
		t.Errorf("EXR after a worker was killed in an adaptive round (%d bytes) differs from the undisturbed one (%d bytes)", len(exrKill), len(exrOne))
	}
}
