package fault

import (
	"flag"
	"math/rand/v2"
	"syscall"
	"testing"
	"time"

	"photonfarm/tests/farmtest"
)

// How many jobs the kill tests disturb: issue 5 asks for 20 worker kills and 10
// coordinator kills (see README.md); the test command runs 4 and 2.
var (
	workerKillTrials      = flag.Int("worker-kill-trials", 4, "worker SIGKILL-and-replace trials (issue 5: 20)")
	coordinatorKillTrials = flag.Int("coordinator-kill-trials", 2, "coordinator SIGKILL-and-restart trials (issue 5: 10)")
)

// TestWorkerKilledInAnyPhaseJobCompletesUnchanged runs a farm on Redis with two workers;
// in each trial, at a random moment of a phase aimed at in turn, it SIGKILLs a random
// worker and starts a replacement. The job must succeed with the undisturbed image, byte
// for byte: the killed worker's lease expires (2 s) and another worker redoes the task.
func TestWorkerKilledInAnyPhaseJobCompletesUnchanged(t *testing.T) {
	f := startRedisFarm(t)
	workers := []*farmtest.Proc{f.StartWorker(t), f.StartWorker(t)}
	for _, w := range workers {
		w.WorkerID(t, 15*time.Second)
	}
	tr := newTrials(t, f, phasedScene(t, f))
	tr.runSpread(t, *workerKillTrials, func(i int, rng *rand.Rand) {
		k := rng.IntN(len(workers))
		victim := workers[k]
		victim.Kill(syscall.SIGKILL)
		<-victim.Done()
		workers[k] = f.StartWorker(t)
		t.Logf("trial %d: SIGKILLed %s, started %s", i, victim.Name, workers[k].Name)
	})
}

// TestCoordinatorKilledInAnyPhaseResumesFromRedis runs a farm on Redis with two workers;
// in each trial, at a random moment of a phase aimed at in turn, it SIGKILLs the
// coordinator and starts another on the same address, data folder and Redis. The job must
// carry on where it stood and succeed with every task succeeded and the undisturbed image,
// byte for byte.
func TestCoordinatorKilledInAnyPhaseResumesFromRedis(t *testing.T) {
	f := startRedisFarm(t)
	f.StartWorker(t)
	f.StartWorker(t)
	tr := newTrials(t, f, phasedScene(t, f))
	tr.runSpread(t, *coordinatorKillTrials, func(i int, _ *rand.Rand) {
		f.RestartCoordinator(t)
		t.Logf("trial %d: SIGKILLed the coordinator and started %s", i, f.Coordinator().Name)
	})
}
