// Package store defines where the coordinator's state lives: jobs, their tasks, and the
// leases workers hold on tasks. Every method is one atomic step, so that an
// implementation over Redis can run each as a single Lua script:
//
//   - CreateJob writes a job with all its tasks and queues the first phase;
//   - LeaseTask pops the next queued task of the phases the caller takes (FIFO by job,
//     then task index), grows its epoch, records the lease and moves the job
//     QUEUED -> RUNNING;
//   - ExtendLeases and ExpireLeases move lease deadlines and requeue expired tasks;
//   - CompleteTask records outputs and, on the last task of a phase, queues the next
//     phase, or on the last task of the job marks it SUCCEEDED with the final outputs;
//   - CompleteRound completes a round's composite, records the round's report and either
//     appends and queues the next round's tasks or marks the job SUCCEEDED: the decision
//     and the completion are one step, so a crash leaves either the composite leased
//     (it is redone after its lease expires, and decided again) or the round fully
//     recorded, never a completed round without a successor or an end;
//   - FailTask requeues the task or, after Options.MaxAttempts failures, fails the job;
//   - ReleaseTask and ReleaseWorker requeue without counting a failure;
//   - CancelJob drops queued tasks and revokes held leases.
//
// Reports about a task (complete, fail, release) name a LeaseRef; one under a retired
// epoch, by another worker, or after the lease expired is refused with an
// errs.FailedPrecondition error. Returned messages are copies the caller may keep.
package store

import (
	"context"
	"strconv"
	"time"

	"photonfarm/coordinator/clock"
	pb "photonfarm/proto/renderfarm/v1"
)

// Store holds jobs, tasks and leases. Implementations: memstore (in process) and
// redisstore (shared by coordinator replicas, survives restarts).
// The behavioural suite in storetest runs against every implementation.
type Store interface {
	// CreateJob stores a new QUEUED job with its tasks and queues the tasks of its first
	// phase. The store assigns the job id and the task ids ("{job_id}.{index}").
	CreateJob(ctx context.Context, j NewJob) (*pb.Job, error)
	// GetJob returns errs.NotFound if the job does not exist.
	GetJob(ctx context.Context, jobID string) (*pb.Job, error)
	// ListJobs lists jobs newest first. An empty next token means the last page.
	ListJobs(ctx context.Context, pageSize int, pageToken string) (jobs []*pb.Job, next string, err error)
	// ListTasks lists a job's tasks in plan order.
	ListTasks(ctx context.Context, jobID string, pageSize int, pageToken string) (tasks []*pb.Task, next string, err error)

	// LeaseTask leases to workerID the next queued task of one of phases (WorkerPhases for
	// workers, BuilderPhases for the coordinator's builder). It returns nil and no error
	// when nothing of those phases is queued, and an error if phases is empty.
	LeaseTask(ctx context.Context, workerID string, phases []pb.Phase) (*Leased, error)
	// ExtendLeases extends the leases workerID still holds among held and returns the
	// others as revoked (expired, re-leased, finished, or their job ended).
	ExtendLeases(ctx context.Context, workerID string, held []*pb.HeldLease) (extended []*pb.Lease, revoked []*pb.HeldLease, err error)
	// ExpireLeases requeues every task whose lease has expired.
	ExpireLeases(ctx context.Context) ([]Change, error)

	// CompleteTask records a task's success. Repeating an accepted report (same worker,
	// same epoch) succeeds and changes nothing (an empty Change).
	CompleteTask(ctx context.Context, ref LeaseRef, outputs []*pb.Artifact) (Change, error)
	// CompleteRound is CompleteTask for the composite task of a progressive round, which
	// must be the round's last task: it records the outputs, appends end.Report to the
	// job's rounds, and then either appends end.Next (renumbered after the job's last task,
	// its first phase queued) or, if end.Next is empty, marks the job SUCCEEDED with
	// end.Final as its outputs. Repeating an accepted report succeeds and changes nothing.
	CompleteRound(ctx context.Context, ref LeaseRef, end RoundEnd) (Change, error)
	// GetTask returns a task; errs.NotFound if it does not exist.
	GetTask(ctx context.Context, taskID string) (*pb.Task, error)
	// FailTask records a failure: the task is queued again, or after MaxAttempts failures
	// it fails and so does its job, with message as the job's error.
	FailTask(ctx context.Context, ref LeaseRef, message string) (Change, error)
	// ReleaseTask queues a leased task again without counting a failure.
	ReleaseTask(ctx context.Context, ref LeaseRef) (Change, error)
	// ReleaseWorker releases every lease workerID holds.
	ReleaseWorker(ctx context.Context, workerID string) ([]Change, error)

	// CancelJob cancels a job that has not ended: its waiting and queued tasks are
	// cancelled and its leases revoked. It returns errs.NotFound for an unknown job and
	// errs.FailedPrecondition for one that has ended.
	CancelJob(ctx context.Context, jobID string) (Change, error)
}

// NewJob is what CreateJob needs.
type NewJob struct {
	DisplayName   string
	SceneDigest   string
	Width, Height uint32
	// Plan is what the planner decided: the passes the job runs and skips.
	Plan *pb.Plan
	// Tasks in plan order, as the planner makes them: Index, Phase, Round and spec set.
	// Stages (round, then phase) run in ascending order; Round 0 counts as 1.
	Tasks []*pb.Task
	// RequestID, if set, is the client's id for this submission: a second CreateJob with
	// the same RequestID creates nothing and returns the job the first one created, so a
	// client may retry a submit whose answer it lost.
	RequestID string
}

// RoundEnd is what CompleteRound records when a round's composite succeeds.
type RoundEnd struct {
	// Outputs of the composite task.
	Outputs []*pb.Artifact
	// Report is appended to Job.rounds.
	Report *pb.RoundReport
	// Next is the next round's tasks in plan order (Index from 0: the store renumbers
	// them after the job's last task). Empty: the job ends here.
	Next []*pb.Task
	// Final is the job's outputs when it ends here.
	Final []*pb.Artifact
}

// Stage orders a job's tasks: by round (0 counts as 1), then by phase. A stage's tasks are
// queued once every task of the stage before has succeeded.
func Stage(t *pb.Task) uint64 {
	return uint64(max(t.GetRound(), 1))<<8 | uint64(t.GetPhase())
}

// The phases each kind of lessee takes: workers never lease BUILD or MERGE, which the
// coordinator's builder does itself.
var (
	WorkerPhases  = []pb.Phase{pb.Phase_PHASE_EMIT, pb.Phase_PHASE_PRECOMPUTE, pb.Phase_PHASE_RENDER, pb.Phase_PHASE_COMPOSITE}
	BuilderPhases = []pb.Phase{pb.Phase_PHASE_BUILD, pb.Phase_PHASE_MERGE}
)

// LeaseRef names the lease a report is made under.
type LeaseRef struct {
	WorkerID string
	TaskID   string
	Epoch    uint64
}

// Leased is a granted lease.
type Leased struct {
	Lease       *pb.Lease
	Task        *pb.Task
	SceneDigest string
	Change      Change
}

// Change says what an operation changed, so that the caller can publish events and wake
// workers waiting for tasks. The zero Change means nothing changed.
type Change struct {
	// Job after the change; nil if nothing changed.
	Job *pb.Job
	// Task that changed, if any.
	Task *pb.Task
	// JobStateChanged is set when Job.State changed.
	JobStateChanged bool
	// Queued is set when tasks were queued (a phase opened or a task went back).
	Queued bool
}

// Options configure a Store implementation.
type Options struct {
	Clock clock.Clock
	// LeaseDuration is how long a lease lasts without being extended.
	LeaseDuration time.Duration
	// MaxAttempts is how many failed attempts a task gets before its job fails.
	MaxAttempts int
}

// Defaults for Options.
const (
	DefaultLeaseDuration = 15 * time.Second
	DefaultMaxAttempts   = 3
)

// WithDefaults fills in unset options.
func (o Options) WithDefaults() Options {
	if o.Clock == nil {
		o.Clock = clock.Real{}
	}
	if o.LeaseDuration <= 0 {
		o.LeaseDuration = DefaultLeaseDuration
	}
	if o.MaxAttempts <= 0 {
		o.MaxAttempts = DefaultMaxAttempts
	}
	return o
}

// TaskID returns the id of a job's task: "{job_id}.{index}".
func TaskID(jobID string, index uint32) string {
	return jobID + "." + strconv.FormatUint(uint64(index), 10)
}

// Ended reports whether a job state is terminal.
func Ended(s pb.JobState) bool {
	return s == pb.JobState_JOB_STATE_SUCCEEDED || s == pb.JobState_JOB_STATE_FAILED || s == pb.JobState_JOB_STATE_CANCELLED
}
