// Package store defines where the coordinator's state lives: jobs, their tasks, and the
// leases workers hold on tasks. Every method is one atomic step, so that an
// implementation over Redis can run each as a single Lua script:
//
//   - CreateJob writes a job with all its tasks and queues the first phase;
//   - LeaseTask pops the next leasable task of the phases the caller takes (see
//     Scheduling), grows its epoch, records the lease and moves the job QUEUED -> RUNNING;
//   - ExtendLeases moves lease deadlines and revokes stuck leases; ExpireLeases requeues
//     expired tasks (see Retries);
//   - CompleteTask records outputs and, on the last task of a phase, queues the next
//     phase, or on the last task of the job marks it SUCCEEDED with the final outputs;
//   - CompleteRound completes a round's composite, records the round's report and either
//     appends and queues the next round's tasks or marks the job SUCCEEDED: the decision
//     and the completion are one step, so a crash leaves either the composite leased
//     (it is redone after its lease expires, and decided again) or the round fully
//     recorded, never a completed round without a successor or an end;
//   - FailTask requeues the task after a backoff or, after Options.MaxAttempts failures,
//     fails the job; a failure of a permanent kind fails the job at once;
//   - FailBlockedJob fails a job that every worker the caller knows is blocked from;
//   - ReleaseTask and ReleaseWorker requeue without counting a failure;
//   - CancelJob drops queued tasks and revokes held leases;
//   - PurgeJobs deletes ended jobs past their retention, a bounded step at a time;
//   - SetJobPriority reorders a job; UnblockWorker takes workers off its blocklist;
//   - ReopenJob reopens a failed or cancelled job where it stopped (RequeueJob, and
//     RetryTask of one of its failed tasks: see Reopening);
//   - DeleteJob cancels a job if need be and hands it to PurgeJobs at once.
//
// Scheduling: LeaseTask picks, among the jobs with a leasable task of the caller's
// phases that have not blocked the caller, the highest Job.priority; among equal
// priorities the job holding the fewest leases now, so that equal jobs share the workers
// instead of running first come, first served; among those the oldest job. Within the job
// it takes the lowest task index.
//
// Retries: what happens to a leased task that does not succeed.
//
//	event                      counts toward   requeued                    blocklist
//	FailTask, transient kind   MaxAttempts     after Backoff(failures)     counts
//	FailTask, resource         MaxAttempts     after Backoff(failures)     does not count
//	  exhausted
//	FailTask, permanent kind   (fails the job at once: retrying cannot help) does not count
//	stuck (no progress for     MaxAttempts     after Backoff(failures)     counts
//	  StuckTimeout)
//	lease expired              MaxExpiries     at once (a lease duration   does not count
//	                                           has passed already)
//	ReleaseTask, cancel        nothing         at once                     does not count
//
// A failure's kind (FailTaskRequest.kind) is permanent or not as its failure_info in the
// contract says (contract/tasks.FailureOf): bad input and unsupported are, so the job
// fails with Job.error "task T failed: E" and Job.failure_kind set, and no worker is
// blamed; any other kind, an unset one included, is transient, and counts toward the
// blocklist if its failure_info says it blames the worker (Failure.BlamesWorker: not
// resource exhaustion, which a healthy worker with a full disk reports). Task.failure_kind is the
// kind of the task's last failure (TRANSIENT for stuck and expired leases), and a job that
// fails at a limit takes its last failure's kind.
//
// A task in backoff is QUEUED with Task.retry_time set and is not leased before then
// (retry_time stays set until the task is leased again). Reaching either limit fails the
// task and its job with "task T failed N times; last error: E". Expiries have a limit of
// their own, larger by default, because a worker that dies is usually not the task's
// fault, while a task that kills every worker it lands on must not retry forever; they do
// not count toward the blocklist because a crashed worker comes back under a new id.
// Stuck: a lease whose HeldLease.progress has not grown for StuckTimeout (progress that
// stays 0 counts as not growing) is revoked at that heartbeat; leases of BuilderPhases
// are exempt (the builder is the coordinator itself and reports no progress).
//
// Blocklist: a worker whose failed attempts at one job's tasks reach BlockAfterFailures
// is added to Job.blocked_workers (reason: the count and its last error) and never leases
// that job's tasks again; the leases it holds stand. UnblockWorker clears it and its
// count. The store does not know which workers exist; the caller does, and
// FailBlockedJob fails a job once every worker it knows is on the job's blocklist (the
// job would otherwise wait for ever).
//
// Reopening: ReopenJob takes a job that ended FAILED or CANCELLED back to where it
// stopped. Its tasks that succeeded stand; those of the stage it stopped in that did not
// are QUEUED again, and those of later stages of the round WAITING, each with its failure
// and expiry counts (MaxAttempts, MaxExpiries) and retry_time reset (Task.attempts, the
// leases granted, and Task.error, the last failure, stay as history). The job's error,
// failure_kind and end_time are cleared and it is QUEUED (RUNNING at its next lease). Its
// blocklist stands: a job every worker is blocked from is failed again by FailBlockedJob
// until UnblockWorker. A report under a lease the end cancelled stays refused.
//
// Reports about a task (complete, fail, release) name a LeaseRef; one under a retired
// epoch, by another worker, or after the lease expired is refused with an
// errs.FailedPrecondition error. Returned messages are copies the caller may keep.
package store

import (
	"cmp"
	"context"
	"fmt"
	"slices"
	"strconv"
	"strings"
	"time"

	"google.golang.org/protobuf/proto"

	"photonfarm/contract/tasks"
	"photonfarm/coordinator/clock"
	"photonfarm/coordinator/errs"
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

	// LeaseTask leases to workerID the next leasable task of one of phases (WorkerPhases
	// for workers, BuilderPhases for the coordinator's builder), in the order described in
	// the package comment. It returns nil and no error when nothing of those phases is
	// leasable by workerID, and an error if phases is empty.
	LeaseTask(ctx context.Context, workerID string, phases []pb.Phase) (*Leased, error)
	// ExtendLeases extends the leases workerID still holds among held, recording their
	// progress, and returns the others as revoked (expired, re-leased, finished, their
	// job ended, or stuck: a stuck lease is also counted as a failed attempt).
	ExtendLeases(ctx context.Context, workerID string, held []*pb.HeldLease) (Heartbeat, error)
	// ExpireLeases requeues every task whose lease has expired, counting an expiry; a task
	// that reaches MaxExpiries fails its job.
	ExpireLeases(ctx context.Context) ([]Change, error)

	// CompleteTask records a task's success. Repeating an accepted report (same worker,
	// same epoch, same outputs) succeeds and changes nothing (an empty Change); a repeat
	// with other outputs is refused (ConflictingReport).
	CompleteTask(ctx context.Context, ref LeaseRef, outputs []*pb.Artifact) (Change, error)
	// CompleteRound is CompleteTask for the composite task of a progressive round, which
	// must be the round's last task: it records the outputs, appends end.Report to the
	// job's rounds, and then either appends end.Next (renumbered after the job's last task,
	// its first phase queued) or, if end.Next is empty, marks the job SUCCEEDED with
	// end.Final as its outputs. Repeating an accepted report succeeds and changes nothing
	// if its outputs and its report's metrics (SameMetrics) are those accepted, and is
	// refused otherwise (ConflictingReport).
	CompleteRound(ctx context.Context, ref LeaseRef, end RoundEnd) (Change, error)
	// GetTask returns a task; errs.NotFound if it does not exist.
	GetTask(ctx context.Context, taskID string) (*pb.Task, error)
	// FailTask records a failure. A permanent one (Failure.Permanent) fails the task and
	// its job at once (PermanentFailure) and counts against no worker. Any other is queued
	// again after a backoff, or after MaxAttempts failures fails with its job (JobFailure),
	// and counts toward the worker's blocklist threshold for the job.
	FailTask(ctx context.Context, ref LeaseRef, f Failure) (Change, error)
	// FailBlockedJob fails the job if workers is not empty and every one of them is on its
	// blocklist (BlockedJobFailure: the count and the latest block's reason; the failure
	// kind is that of the failure that made the latest block); otherwise, or if the job
	// has ended, it changes nothing. It returns errs.NotFound for an unknown job.
	FailBlockedJob(ctx context.Context, jobID string, workers []string) (Change, error)
	// ReleaseTask queues a leased task again without counting a failure.
	ReleaseTask(ctx context.Context, ref LeaseRef) (Change, error)
	// ReleaseWorker releases every lease workerID holds.
	ReleaseWorker(ctx context.Context, workerID string) ([]Change, error)

	// CancelJob cancels a job that has not ended: its waiting and queued tasks are
	// cancelled and its leases revoked. It returns errs.NotFound for an unknown job and
	// errs.FailedPrecondition for one that has ended.
	CancelJob(ctx context.Context, jobID string) (Change, error)
	// SetJobPriority sets a job's priority (CheckPriority); leases granted stand. It
	// returns errs.NotFound for an unknown job and errs.FailedPrecondition for an ended
	// one.
	SetJobPriority(ctx context.Context, jobID string, priority int32) (Change, error)
	// PurgeJobs deletes, in one bounded step, the jobs that ended before endedBefore and
	// those whose creation was abandoned midway (not finished, and not grown since
	// abandonedBefore: a coordinator died making it), with their tasks, round reports and
	// request ids. A job being deleted is gone for every read at once. A step deletes about
	// budget task records at most, so that a large job takes several; Purge.More says to
	// call again.
	PurgeJobs(ctx context.Context, endedBefore, abandonedBefore time.Time, budget int) (Purge, error)

	// ReopenJob reopens a job that ended FAILED or CANCELLED (see Reopening). If
	// failedTask is not empty it must name a FAILED task of the job (RetryTask). It
	// returns errs.NotFound for an unknown job or task and errs.FailedPrecondition for a
	// job that succeeded or has not ended, or a task that has not failed (CheckReopen,
	// CheckRetry). The Change has JobStateChanged and Queued set, and Task if failedTask
	// was given.
	ReopenJob(ctx context.Context, jobID, failedTask string) (Change, error)
	// DeleteJob cancels the job if it has not ended and, in the same step, marks it for
	// PurgeJobs: from then on it is gone for every read (NotFound, left out of ListJobs)
	// and for every report, and the next PurgeJobs steps delete its records whatever the
	// times they are given. The Change is the job as it was deleted, JobStateChanged if it
	// was cancelled. It returns errs.NotFound for an unknown job.
	DeleteJob(ctx context.Context, jobID string) (Change, error)

	// UnblockWorker takes workerID (every worker if empty) off the job's blocklist and
	// resets its failure count; unblocking a worker that is not blocked changes nothing.
	// It returns errs.NotFound for an unknown job.
	UnblockWorker(ctx context.Context, jobID, workerID string) (Change, error)
}

// Purge is what a PurgeJobs step did.
type Purge struct {
	Deleted []string // the jobs deleted
	More    bool     // there is more to delete: call again
}

// Heartbeat is what ExtendLeases did.
type Heartbeat struct {
	Extended []*pb.Lease
	Revoked  []*pb.HeldLease
	// Changes made by revoking stuck leases, one per lease.
	Changes []Change
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
	// Priority in [MinPriority, MaxPriority]: higher jobs are leased first.
	Priority int32
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

// Stage orders a job's tasks: by round (0 counts as 1), then by the rank of the phase in
// the contract's table (the order job.proto declares the phases in, not their numbers).
// A stage's tasks are queued once every task of the stage before has succeeded.
func Stage(t *pb.Task) uint64 { return StageIn(tasks.Phases, t.GetRound(), t.GetPhase()) }

// StageIn is the stage of a task of phase in round under the phase table table: the round
// in the high bits, the phase's rank (from 1; 0 for a phase the table lacks) in the low 8.
func StageIn(table tasks.Table, round uint32, phase pb.Phase) uint64 {
	return uint64(max(round, 1))<<8 | uint64(table.Rank(phase))
}

// The phases each kind of lessee takes, as the contract declares their executors: workers
// never lease BUILD or MERGE, which the coordinator's builder does itself.
var (
	WorkerPhases  = tasks.Phases.RunBy(pb.Executor_EXECUTOR_WORKER)
	BuilderPhases = tasks.Phases.RunBy(pb.Executor_EXECUTOR_COORDINATOR)
)

// Failure is what a failed attempt reports (FailTaskRequest): why, and of what kind.
type Failure struct {
	Message string
	Kind    pb.FailureKind
	// The attempt's log ("task.log"), if the worker sent one: the task's Task.log from
	// then on. Nil keeps the log of an earlier attempt.
	Log *pb.Artifact
}

// Permanent reports whether retrying cannot help, as the kind's failure_info says; an
// unset or unknown kind is transient.
func (f Failure) Permanent() bool { return tasks.FailureOf(f.Kind).Permanent }

// BlamesWorker reports whether the failed attempt counts toward the worker's blocklist
// threshold, as the kind's failure_info says: transient and unset kinds do, resource
// exhaustion (a full disk or cache) and the permanent kinds do not.
func (f Failure) BlamesWorker() bool { return tasks.FailureOf(f.Kind).BlamesWorker }

// Transient is a failure of the transient kind: what stuck and expired leases record.
func Transient(message string) Failure {
	return Failure{Message: message, Kind: pb.FailureKind_FAILURE_KIND_TRANSIENT}
}

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
	// StageStart and StageEnd bound the task's stage: the job's tasks [StageStart,
	// StageEnd), so that the caller finds the stages before it (whose outputs the task
	// needs) without reading the rest of the job.
	StageStart, StageEnd uint32
	Change               Change
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
	// Queued is set when tasks became leasable (a phase opened, a task went back without
	// a backoff, a worker was unblocked). A task put back with a backoff does not set it:
	// its Task.retry_time says when to look again.
	Queued bool
}

// Options configure a Store implementation.
type Options struct {
	Clock clock.Clock
	// LeaseDuration is how long a lease lasts without being extended.
	LeaseDuration time.Duration
	// MaxAttempts is how many failed attempts (FailTask, stuck leases) a task gets
	// before its job fails.
	MaxAttempts int
	// MaxExpiries is how many of a task's leases may expire before its job fails.
	MaxExpiries int
	// BlockAfterFailures is how many failed attempts at one job's tasks block a worker
	// from the job.
	BlockAfterFailures int
	// RetryBackoff and MaxRetryBackoff bound the wait before a failed task is leased
	// again (Backoff).
	RetryBackoff, MaxRetryBackoff time.Duration
	// StuckTimeout is how long a lease may go without its progress growing.
	StuckTimeout time.Duration
}

// Defaults for Options (docs/limits.md, "Leases and retries").
const (
	DefaultLeaseDuration      = 15 * time.Second
	DefaultMaxAttempts        = 3
	DefaultMaxExpiries        = 5
	DefaultBlockAfterFailures = 3
	DefaultRetryBackoff       = time.Second
	DefaultMaxRetryBackoff    = time.Minute
	DefaultStuckTimeout       = 10 * time.Minute
)

// WithDefaults fills in unset options; a count or duration that is not positive is unset.
func (o Options) WithDefaults() Options {
	if o.Clock == nil {
		o.Clock = clock.Real{}
	}
	o.LeaseDuration = cmp.Or(max(o.LeaseDuration, 0), DefaultLeaseDuration)
	o.MaxAttempts = cmp.Or(max(o.MaxAttempts, 0), DefaultMaxAttempts)
	o.MaxExpiries = cmp.Or(max(o.MaxExpiries, 0), DefaultMaxExpiries)
	o.BlockAfterFailures = cmp.Or(max(o.BlockAfterFailures, 0), DefaultBlockAfterFailures)
	o.RetryBackoff = cmp.Or(max(o.RetryBackoff, 0), DefaultRetryBackoff)
	o.MaxRetryBackoff = cmp.Or(max(o.MaxRetryBackoff, 0), DefaultMaxRetryBackoff)
	o.StuckTimeout = cmp.Or(max(o.StuckTimeout, 0), DefaultStuckTimeout)
	return o
}

// Backoff is how long a task waits after its n-th failed attempt (n >= 1):
// RetryBackoff·2^(n-1), at most MaxRetryBackoff. (redisstore's Lua fail() computes the
// same from the policy argument.)
func (o Options) Backoff(n int) time.Duration {
	d := o.RetryBackoff
	for i := 1; i < n && d < o.MaxRetryBackoff; i++ {
		d *= 2
	}
	return min(d, o.MaxRetryBackoff)
}

// StuckMessage is the failure recorded for a lease revoked as stuck.
func (o Options) StuckMessage() string {
	return "no progress for " + o.StuckTimeout.String() + " (stuck)"
}

// ExpiredMessage is the failure recorded for an expired lease.
const ExpiredMessage = "lease expired (worker lost)"

// JobFailure is the job's error when its task taskID reached a limit after n failures.
func JobFailure(taskID string, n int, last string) string {
	return fmt.Sprintf("task %s failed %d times; last error: %s", taskID, n, last)
}

// PermanentFailure is the job's error when its task taskID failed for good.
func PermanentFailure(taskID, message string) string {
	return fmt.Sprintf("task %s failed: %s", taskID, message)
}

// ConflictingReport refuses a repeat of an accepted report under ref whose what
// ("outputs", "metrics") differ from those accepted: one of the two is wrong, and the
// first stands.
func ConflictingReport(ref LeaseRef, what string) error {
	return errs.E(errs.FailedPrecondition, "task %s: lease epoch %d was already completed with other %s; a repeated report must be the same",
		ref.TaskID, ref.Epoch, what)
}

// SameOutputs reports whether two reports' outputs are the same artifacts in the same
// order.
func SameOutputs(a, b []*pb.Artifact) bool {
	return slices.EqualFunc(a, b, func(x, y *pb.Artifact) bool { return proto.Equal(x, y) })
}

// Metrics is the part of a round's report the composite's worker measured
// (CompleteTaskRequest.metrics); the rest is the coordinator's (elapsed time, counts).
func Metrics(r *pb.RoundReport) *pb.RoundMetrics {
	return &pb.RoundMetrics{
		ErrorEstimate: r.ErrorEstimate, ReferenceRmse: r.ReferenceRmse, LayerReferenceRmse: r.GetLayerReferenceRmse(),
		ErrorEstimateBias: r.ErrorEstimateBias, ErrorEstimateLow: r.ErrorEstimateLow, ErrorEstimateHigh: r.ErrorEstimateHigh,
	}
}

// SameMetrics reports whether two round reports carry the same metrics.
func SameMetrics(a, b *pb.RoundReport) bool { return proto.Equal(Metrics(a), Metrics(b)) }

// BlockedJobFailure is the job's error when every one of n workers is blocked from it;
// last is the reason of the latest block.
func BlockedJobFailure(n int, last string) string {
	return fmt.Sprintf("every worker (%d) is blocked from this job; last: %s", n, last)
}

// BlockReason is Job.blocked_workers[i].reason for a worker blocked after n failures.
func BlockReason(n int, last string) string {
	return fmt.Sprintf("%d failed tasks: %s", n, last)
}

// Job priorities (Job.priority).
const (
	MinPriority = -1000
	MaxPriority = 1000
)

// CheckPriority refuses a priority outside [MinPriority, MaxPriority], naming the field.
func CheckPriority(p int32) error {
	if p < MinPriority || p > MaxPriority {
		return errs.Field("priority", "must be in [%d, %d], got %d", MinPriority, MaxPriority, p)
	}
	return nil
}

// Exempt reports whether leases of phase are exempt from the stuck timeout: the
// builder's, which the coordinator runs itself.
func Exempt(phase pb.Phase) bool {
	return slices.Contains(BuilderPhases, phase)
}

// SortBlocked orders a blocklist by block time, then worker id, so that every store
// lists it alike.
func SortBlocked(bs []*pb.BlockedWorker) {
	slices.SortFunc(bs, func(a, b *pb.BlockedWorker) int {
		if c := a.GetBlockTime().AsTime().Compare(b.GetBlockTime().AsTime()); c != 0 {
			return c
		}
		return strings.Compare(a.GetWorkerId(), b.GetWorkerId())
	})
}

// TaskID returns the id of a job's task: "{job_id}.{index}".
func TaskID(jobID string, index uint32) string {
	return jobID + "." + strconv.FormatUint(uint64(index), 10)
}

// Ended reports whether a job state is terminal.
func Ended(s pb.JobState) bool {
	return s == pb.JobState_JOB_STATE_SUCCEEDED || s == pb.JobState_JOB_STATE_FAILED || s == pb.JobState_JOB_STATE_CANCELLED
}

// JobOfTask returns the id of the job a task id ("{job_id}.{index}") names, and false for
// an id of no task.
func JobOfTask(taskID string) (string, bool) {
	k := strings.LastIndexByte(taskID, '.')
	if k <= 0 {
		return "", false
	}
	if _, err := strconv.ParseUint(taskID[k+1:], 10, 32); err != nil {
		return "", false
	}
	return taskID[:k], true
}

// CheckReopen refuses to reopen a job in state: only a FAILED or CANCELLED one can be.
// (redisstore's reopenScript words its refusals alike.)
func CheckReopen(jobID string, state pb.JobState) error {
	switch state {
	case pb.JobState_JOB_STATE_FAILED, pb.JobState_JOB_STATE_CANCELLED:
		return nil
	case pb.JobState_JOB_STATE_SUCCEEDED:
		return errs.E(errs.FailedPrecondition, "job %s succeeded: only a failed or cancelled job can be requeued", jobID)
	}
	return errs.E(errs.FailedPrecondition, "job %s has not ended (%s): only a failed or cancelled job can be requeued", jobID, state)
}

// CheckRetry refuses to retry a task in state: only a FAILED one can be.
func CheckRetry(taskID string, state pb.TaskState) error {
	if state == pb.TaskState_TASK_STATE_FAILED {
		return nil
	}
	return errs.E(errs.FailedPrecondition, "task %s is %s, not failed: only a failed task can be retried", taskID, state)
}
