package fault

import (
	"bytes"
	"math/rand/v2"
	"testing"
	"time"

	"photonfarm/client"
	"photonfarm/contract/tasks"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

// phaseOrder is the order of the phases the trials may aim at.
var phaseOrder = []pb.Phase{
	pb.Phase_PHASE_EMIT, pb.Phase_PHASE_BUILD, pb.Phase_PHASE_PRECOMPUTE,
	pb.Phase_PHASE_MERGE, pb.Phase_PHASE_RENDER, pb.Phase_PHASE_COMPOSITE,
}

// minAimable is the shortest undisturbed phase a trial aims at: ten polls. A shorter one
// (the kd-tree build and merge take a few milliseconds on this scene) is usually over by
// the time the fault comes, so aiming at it would only land a second fault in the next.
const minAimable = 20 * time.Millisecond

// aimable lists, in order, the phases of tl long enough to aim at.
func aimable(tl timeline) []pb.Phase {
	var out []pb.Phase
	for _, p := range phaseOrder {
		if tl[p] >= minAimable {
			out = append(out, p)
		}
	}
	return out
}

// trials runs jobs of one scene on one farm, disturbing each at a random moment.
type trials struct {
	f         *farmtest.Farm
	sc        *pb.Scene
	reference []byte     // the undisturbed render's EXR
	timeline  timeline   // the undisturbed render's phases
	targets   []pb.Phase // the phases trials aim at in turn, from one that depends on the seed
	seed      uint64
	landed    map[string]int // how many faults landed in each phase ("ended" after the last)
}

// newTrials renders sc twice undisturbed: the first render warms the workers up (their
// first task loads the scene), the second gives the phase durations the trials draw their
// delays from, and both must give the same image, the trials' reference.
func newTrials(t *testing.T, f *farmtest.Farm, sc *pb.Scene) *trials {
	t.Helper()
	first, cold := renderTimed(t, f, sc, 2*time.Minute)
	reference, tl := renderTimed(t, f, sc, 2*time.Minute)
	t.Logf("undisturbed renders: %d-byte EXR; phases with cold workers: %s; warm: %s", len(reference), cold, tl)
	if !bytes.Equal(farmtest.WithoutRenderTime(first), farmtest.WithoutRenderTime(reference)) {
		t.Fatalf("two undisturbed renders of one scene differ (%d and %d bytes)", len(first), len(reference))
	}
	targets := aimable(tl)
	if len(targets) == 0 {
		t.Fatalf("no phase of the undisturbed render lasted %s or more (%s): nothing to aim at", minAimable, tl)
	}
	return &trials{f: f, sc: sc, reference: reference, timeline: tl, targets: targets, seed: seed(t), landed: map[string]int{}}
}

// run is trial i: it submits the scene, waits until the job reaches the trial's target
// phase, then for a random part of the first three quarters of that phase's undisturbed
// duration (the poll that saw the phase start came some time into it), logs where the job
// stands and calls fault (with the trial's random source) to disturb it. The job must then
// succeed with every task succeeded and an EXR byte-identical to the undisturbed one.
func (tr *trials) run(t *testing.T, i int, fault func(rng *rand.Rand)) {
	t.Helper()
	rng := trialRNG(tr.seed, i)
	target := tr.targets[(i+int(tr.seed%uint64(len(tr.targets))))%len(tr.targets)]
	delay := time.Duration(rng.Float64() * 0.75 * float64(tr.timeline[target]))
	job := tr.f.Submit(t, tr.sc)
	tr.waitForPhase(t, job.GetId(), target)
	time.Sleep(delay)
	phase, where := snapshot(t, tr.f, job.GetId())
	tr.landed[phase]++
	t.Logf("trial %d: aimed at %s + %s; the job was in %s", i, tasks.Name(target), delay.Round(time.Millisecond), where)
	fault(rng)

	done := tr.f.Wait(t, job.GetId(), 2*time.Minute)
	if got := tr.f.Output(t, done, "image.exr"); !bytes.Equal(farmtest.WithoutRenderTime(got), farmtest.WithoutRenderTime(tr.reference)) {
		t.Errorf("trial %d (seed %d): the EXR (%d bytes) differs from the undisturbed render's (%d bytes)", i, tr.seed, len(got), len(tr.reference))
	}
	retried := 0
	for _, task := range tr.f.Tasks(t, job.GetId()) {
		if task.GetState() != pb.TaskState_TASK_STATE_SUCCEEDED {
			t.Errorf("trial %d (seed %d): task %s is %v: %s", i, tr.seed, task.GetId(), task.GetState(), task.GetError())
		}
		if task.GetAttempts() > 1 {
			retried++
		}
	}
	t.Logf("trial %d: job %s succeeded, byte-identical; %d tasks took more than one lease", i, job.GetId(), retried)
}

// waitForPhase waits until the job is in phase target or past it (a phase can end between
// two polls).
func (tr *trials) waitForPhase(t *testing.T, jobID string, target pb.Phase) {
	t.Helper()
	for deadline := time.Now().Add(time.Minute); ; time.Sleep(2 * time.Millisecond) {
		job := getJob(t, tr.f, jobID)
		if p := currentPhase(job); p >= target || client.JobEnded(job.GetState()) {
			return
		}
		if time.Now().After(deadline) {
			t.Fatalf("job %s did not reach %s within a minute: %v", jobID, tasks.Name(target), job)
		}
	}
}

// runSpread runs n trials, then, while their faults have landed in fewer phases than
// spreadWanted asks for, up to n more, each aimed at the next phase in turn; then checks the
// spread. A fault aimed at a phase can land in the next one (a phase can end between two
// polls, or while the fault is being set up on a loaded machine), and with two trials aimed
// at neighbouring phases both can land in the second: the extra trials keep the point of
// aiming (every phase disturbed, not the longest one n times) without failing on timing.
// Every trial, extra ones included, must give the undisturbed image.
func (tr *trials) runSpread(t *testing.T, n int, fault func(i int, rng *rand.Rand)) {
	t.Helper()
	want := tr.spreadWanted(n)
	for i := 0; i < n || (len(tr.landed) < want && i < 2*n); i++ {
		if i == n {
			t.Logf("the faults of %d trials landed in %d phases (%v), fewer than %d: more trials", n, len(tr.landed), tr.landed, want)
		}
		tr.run(t, i, func(rng *rand.Rand) { fault(i, rng) })
	}
	tr.checkSpread(t, want)
}

// spreadWanted is how many distinct phases the faults of n trials must land in: min(n, 3,
// aimable phases), since a phase can end between two polls.
func (tr *trials) spreadWanted(n int) int { return min(n, 3, len(tr.targets)) }

// checkSpread fails the test if the faults landed in fewer than want phases.
func (tr *trials) checkSpread(t *testing.T, want int) {
	t.Helper()
	t.Logf("faults landed in: %v", tr.landed)
	if len(tr.landed) < want {
		t.Errorf("the faults landed in %d phases (%v); want at least %d", len(tr.landed), tr.landed, want)
	}
}
