// Package storetest is the behavioural test suite every store.Store implementation must
// pass. An implementation's tests call Run with a constructor:
//
//	func TestStore(t *testing.T) {
//		storetest.Run(t, func(t *testing.T, opts store.Options) store.Store { return memstore.New(opts) })
//	}
//
// The constructor must honour opts (the suite passes a fake clock, a lease duration and the
// retry limits) and return an empty store.
package storetest

import (
	"context"
	"fmt"
	"strings"
	"testing"
	"time"

	"photonfarm/coordinator/clock"
	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// NewStoreFunc makes an empty store configured by opts.
type NewStoreFunc func(t *testing.T, opts store.Options) store.Store

const (
	leaseDuration = 10 * time.Second
	maxAttempts   = 3
	maxExpiries   = 4
	blockAfter    = 3
	stuckTimeout  = time.Minute
)

var start = time.Date(2030, 1, 2, 3, 4, 5, 0, time.UTC)

// fixture is one test's store, fake clock and context.
type fixture struct {
	t     *testing.T
	ctx   context.Context
	clock *clock.Fake
	opts  store.Options // as the store got them, defaults filled in
	s     store.Store
	// newStore made s: fresh makes another store for a subtest.
	newStore NewStoreFunc
}

// fresh is a fixture of an empty store of the same kind, for subtest t.
func (f *fixture) fresh(t *testing.T) *fixture { return setup(t, f.newStore) }

func setup(t *testing.T, newStore NewStoreFunc) *fixture {
	t.Helper()
	clk := clock.NewFake(start)
	opts := store.Options{Clock: clk, LeaseDuration: leaseDuration, MaxAttempts: maxAttempts,
		MaxExpiries: maxExpiries, BlockAfterFailures: blockAfter, StuckTimeout: stuckTimeout}.WithDefaults()
	return &fixture{t: t, ctx: context.Background(), clock: clk, opts: opts, s: newStore(t, opts), newStore: newStore}
}

// Run runs the whole suite against the implementation newStore makes.
func Run(t *testing.T, newStore NewStoreFunc) {
	tests := []struct {
		name string
		fn   func(*fixture)
	}{
		{"CreateJobQueuesFirstPhase", testCreateJob},
		{"CreateJobWithSeenRequestIDReturnsTheFirstJob", testCreateJobRequestID},
		{"GetJobUnknownIsNotFound", testGetJobUnknown},
		{"LeaseNothingQueuedIsNotAnError", testLeaseNothing},
		{"EqualJobsShareLeasesThenIndexOrder", testLeaseShares},
		{"HigherPriorityIsLeasedFirst", testPriorityOrder},
		{"FewestHeldLeasesGoesNextAmongEquals", testFairShare},
		{"SetJobPriorityReorders", testSetJobPriority},
		{"FailedTaskWaitsForItsBackoff", testBackoff},
		{"ExpiriesCountTowardTheirLimit", testExpiryLimit},
		{"WorkerIsBlockedAfterFailuresUntilUnblocked", testBlocklist},
		{"LeaseWithoutProgressIsRevokedAsStuck", testStuck},
		{"FirstLeaseStartsJob", testFirstLeaseStartsJob},
		{"LastTileOpensCompositePhase", testPhaseOpening},
		{"LastTaskSucceedsJobWithCompositeOutputs", testJobSucceeds},
		{"RepeatedCompleteIsIdempotent", testIdempotentComplete},
		{"RepeatedReportWithOtherOutputsOrMetricsIsRefused", testRepeatedReportsMustBeTheSame},
		{"ReportsUnderStaleEpochOrOtherWorkerAreRefused", testStaleReports},
		{"ExpiredLeaseIsRequeuedWithNewEpoch", testExpiry},
		{"ReportAfterExpiryBeforeSweepIsRefused", testReportAfterDeadline},
		{"HeartbeatExtendsAndRevokes", testExtend},
		{"FailureRetriesThenFailsJob", testFailRetries},
		{"ReleaseDoesNotCountAsFailure", testRelease},
		{"ReleaseWorkerRequeuesItsLeases", testReleaseWorker},
		{"CancelDropsQueuedAndRevokesLeases", testCancel},
		{"ListJobsNewestFirstWithPages", testListJobs},
		{"ListTasksInPlanOrderWithPages", testListTasks},
		{"ConcurrentLeasesNeverShareATask", testConcurrentLeases},
		{"LeaseNeedsPhases", testLeaseNeedsPhases},
		{"LeaseIsFilteredByPhase", testLeasePhaseFilter},
		{"PhasesOpenInOrderEmitBuildRenderComposite", testPhotonPhasesOpenInOrder},
		{"JobWithoutPhotonsStartsAtRender", testJobWithoutPhotons},
		{"ExpiredBuildLeaseIsRequeuedForTheBuilder", testBuildLeaseExpiry},
		{"CompleteRoundAppendsTheNextRoundThenEndsTheJob", testCompleteRoundAppendsNextRound},
		{"CompleteRoundRefusesTilesAndStaleLeases", testCompleteRoundRefusals},
		{"CancelledJobGetsNoNewRound", testCancelledRoundIsNotExtended},
		{"PermanentFailureFailsTheJobAtOnceAndBlamesNoWorker", testPermanentFailure},
		{"TransientKindsRetryAndRecordTheirKind", testTransientKinds},
		{"ResourceExhaustionRetriesWithoutBlamingTheWorker", testResourceExhaustionBlamesNoWorker},
		{"TaskKeepsTheLastFailedAttemptsLogAndASuccessOnesInItsOutputs", testTaskLogs},
		{"JobEveryGivenWorkerIsBlockedFromFailsWithTheLatestBlock", testFailBlockedJob},
		{"PurgeDeletesEndedJobsWithTheirTasksAndRequestIDs", testPurgeDeletesEndedJobs},
		{"PurgeGoesInBoundedSteps", testPurgeGoesInBoundedSteps},
		{"RequeueReopensWhereTheJobStopped", testRequeueReopensWhereTheJobStopped},
		{"RetryTaskQueuesItAndReopensTheJob", testRetryTaskQueuesItAndReopensTheJob},
		{"ReopenRefusesJobsNotFailedOrCancelledAndTasksNotFailed", testReopenRefusals},
		{"DeleteJobIsGoneAtOnceAndPurgedAfter", testDeleteJobIsGoneAtOnce},
	}
	for _, tt := range tests {
		t.Run(tt.name, func(t *testing.T) { tt.fn(setup(t, newStore)) })
	}
}

// TileJob makes a job of `tiles` render tasks and one composite task: the suite's plain
// job, which an implementation's own tests (concurrency, durability, scale) use too.
func TileJob(name string, tiles int) store.NewJob {
	nj := store.NewJob{DisplayName: name, SceneDigest: digest(name), Width: uint32(8 * tiles), Height: 8}
	for i := 0; i < tiles; i++ {
		nj.Tasks = append(nj.Tasks, &pb.Task{Index: uint32(i), Phase: pb.Phase_PHASE_RENDER,
			Spec: &pb.Task_RenderTile{RenderTile: &pb.RenderTileSpec{Rect: &pb.PixelRect{X: uint32(8 * i), Width: 8, Height: 8}}}})
	}
	nj.Tasks = append(nj.Tasks, &pb.Task{Index: uint32(tiles), Phase: pb.Phase_PHASE_COMPOSITE,
		Spec: &pb.Task_Composite{Composite: &pb.CompositeSpec{}}})
	return nj
}

// newPhotonJob makes a job of `shards` emit tasks, one build task, `tiles` render tasks
// and one composite task.
func newPhotonJob(name string, shards, tiles int) store.NewJob {
	nj := store.NewJob{DisplayName: name, SceneDigest: digest(name), Width: uint32(8 * tiles), Height: 8}
	add := func(t *pb.Task) {
		t.Index = uint32(len(nj.Tasks))
		nj.Tasks = append(nj.Tasks, t)
	}
	for i := 0; i < shards; i++ {
		add(&pb.Task{Phase: pb.Phase_PHASE_EMIT, Spec: &pb.Task_EmitPhotons{EmitPhotons: &pb.EmitPhotonsSpec{
			Map: pb.PhotonMapKind_PHOTON_MAP_KIND_GLOBAL, FirstPhoton: uint64(1000 * i), PhotonCount: 1000, TotalPhotons: uint64(1000 * shards)}}})
	}
	add(&pb.Task{Phase: pb.Phase_PHASE_BUILD, Spec: &pb.Task_BuildPhotonMap{BuildPhotonMap: &pb.BuildPhotonMapSpec{}}})
	for i := 0; i < tiles; i++ {
		add(&pb.Task{Phase: pb.Phase_PHASE_RENDER,
			Spec: &pb.Task_RenderTile{RenderTile: &pb.RenderTileSpec{Rect: &pb.PixelRect{X: uint32(8 * i), Width: 8, Height: 8}}}})
	}
	add(&pb.Task{Phase: pb.Phase_PHASE_COMPOSITE, Spec: &pb.Task_Composite{Composite: &pb.CompositeSpec{}}})
	return nj
}

func (f *fixture) createPhotonJob(name string, shards, tiles int) *pb.Job {
	f.t.Helper()
	j, err := f.s.CreateJob(f.ctx, newPhotonJob(name, shards, tiles))
	if err != nil {
		f.t.Fatalf("CreateJob: %v", err)
	}
	return j
}

func digest(s string) string {
	h := fmt.Sprintf("%x", []byte(s))
	return "sha256:" + (h + strings.Repeat("0", 64))[:64]
}

func artifact(name, of string) *pb.Artifact {
	return &pb.Artifact{Name: name, Digest: digest(of), SizeBytes: int64(len(of))}
}

func (f *fixture) create(name string, tiles int) *pb.Job {
	f.t.Helper()
	j, err := f.s.CreateJob(f.ctx, TileJob(name, tiles))
	if err != nil {
		f.t.Fatalf("CreateJob: %v", err)
	}
	return j
}

// lease leases a task of the phases workers take.
func (f *fixture) lease(worker string) *store.Leased {
	f.t.Helper()
	return f.leaseOf(worker, store.WorkerPhases)
}

func (f *fixture) leaseOf(worker string, phases []pb.Phase) *store.Leased {
	f.t.Helper()
	l, err := f.s.LeaseTask(f.ctx, worker, phases)
	if err != nil {
		f.t.Fatalf("LeaseTask(%s, %v): %v", worker, phases, err)
	}
	if l == nil {
		f.t.Fatalf("LeaseTask(%s, %v): nothing queued, want a task", worker, phases)
	}
	return l
}

func (f *fixture) noLease(worker string) {
	f.t.Helper()
	f.noLeaseOf(worker, store.WorkerPhases)
}

func (f *fixture) noLeaseOf(worker string, phases []pb.Phase) {
	f.t.Helper()
	l, err := f.s.LeaseTask(f.ctx, worker, phases)
	if err != nil || l != nil {
		f.t.Fatalf("LeaseTask(%s, %v) = %v, %v; want nothing to do", worker, phases, l, err)
	}
}

func ref(worker string, l *store.Leased) store.LeaseRef {
	return store.LeaseRef{WorkerID: worker, TaskID: l.Lease.TaskId, Epoch: l.Lease.Epoch}
}

func (f *fixture) complete(worker string, l *store.Leased, outs ...*pb.Artifact) store.Change {
	f.t.Helper()
	c, err := f.s.CompleteTask(f.ctx, ref(worker, l), outs)
	if err != nil {
		f.t.Fatalf("CompleteTask(%s): %v", l.Lease.TaskId, err)
	}
	return c
}

func (f *fixture) job(id string) *pb.Job {
	f.t.Helper()
	j, err := f.s.GetJob(f.ctx, id)
	if err != nil {
		f.t.Fatalf("GetJob: %v", err)
	}
	return j
}

func (f *fixture) tasks(jobID string) []*pb.Task {
	f.t.Helper()
	ts, _, err := f.s.ListTasks(f.ctx, jobID, 10000, "")
	if err != nil {
		f.t.Fatalf("ListTasks: %v", err)
	}
	return ts
}

func wantKind(t *testing.T, what string, err error, k errs.Kind) {
	t.Helper()
	if err == nil || errs.KindOf(err) != k {
		t.Fatalf("%s: err = %v, want kind %v", what, err, k)
	}
}

func taskStates(ts []*pb.Task) string {
	var b strings.Builder
	for _, t := range ts {
		b.WriteString(strings.TrimPrefix(t.State.String(), "TASK_STATE_")[:1])
	}
	return b.String()
}
