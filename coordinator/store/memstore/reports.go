package memstore

import (
	"container/heap"
	"context"
	"slices"
	"time"

	"google.golang.org/protobuf/proto"
	"google.golang.org/protobuf/types/known/timestamppb"

	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// CompleteTask implements store.Store.
func (s *Store) CompleteTask(ctx context.Context, ref store.LeaseRef, outputs []*pb.Artifact) (store.Change, error) {
	s.mu.Lock()
	defer s.mu.Unlock()
	if t := s.repeated(ref); t != nil { // a repeated report that was accepted
		if !store.SameOutputs(t.pb.Outputs, outputs) {
			return store.Change{}, store.ConflictingReport(ref, "outputs")
		}
		return store.Change{}, nil
	}
	t, err := s.held(ref)
	if err != nil {
		return store.Change{}, err
	}
	s.succeed(t, outputs)
	j := t.job
	if j.left > 0 {
		return s.change(t, false, false), nil
	}
	// That was the stage's last task: open the next stage, or the job succeeded with the
	// outputs of this one.
	if j.end < len(j.tasks) {
		s.openStage(j, j.end)
		return s.change(t, false, true), nil
	}
	var final []*pb.Artifact
	for _, o := range j.tasks[j.cur:j.end] {
		final = append(final, o.pb.Outputs...)
	}
	s.succeedJob(j, final)
	return s.change(t, true, false), nil
}

// CompleteRound implements store.Store. The next round's tasks are built before the lock
// is taken.
func (s *Store) CompleteRound(ctx context.Context, ref store.LeaseRef, end store.RoundEnd) (store.Change, error) {
	if end.Report == nil {
		return store.Change{}, errs.E(errs.Internal, "CompleteRound needs the round's report")
	}
	if err := store.CheckPlan(end.Next); err != nil {
		return store.Change{}, errs.Wrap(errs.Internal, err, "next round")
	}
	next := newTasks(nil, end.Next, 0)
	report := proto.Clone(end.Report).(*pb.RoundReport)

	s.mu.Lock()
	defer s.mu.Unlock()
	if t := s.repeated(ref); t != nil {
		return store.Change{}, t.sameRound(ref, end)
	}
	t, err := s.held(ref)
	if err != nil {
		return store.Change{}, err
	}
	j := t.job
	if int(t.pb.Index) != len(j.tasks)-1 || j.cur != len(j.tasks)-1 {
		return store.Change{}, errs.E(errs.Internal, "task %s is not the last task of its round", t.pb.Id)
	}
	if len(next) > 0 && store.Stage(next[0].pb) <= store.Stage(t.pb) {
		return store.Change{}, errs.E(errs.Internal, "next round's task 0 is out of order")
	}
	s.succeed(t, end.Outputs)
	j.pb.Rounds = append(j.pb.Rounds, report)
	if len(next) > 0 {
		base := len(j.tasks)
		for _, n := range next {
			n.job = j
			n.pb.Index += uint32(base)
			n.pb.JobId = j.pb.Id
			n.pb.Id = store.TaskID(j.pb.Id, n.pb.Index)
		}
		j.tasks = append(j.tasks, next...)
		s.openRound(j, base)
		return s.change(t, false, true), nil
	}
	s.succeedJob(j, end.Final)
	return s.change(t, true, false), nil
}

// repeated returns the task ref names if it already succeeded under that lease.
func (s *Store) repeated(ref store.LeaseRef) *task {
	t := s.task(ref.TaskID)
	if t != nil && t.pb.State == pb.TaskState_TASK_STATE_SUCCEEDED && t.epoch == ref.Epoch && t.pb.WorkerId == ref.WorkerID {
		return t
	}
	return nil
}

// sameRound refuses a repeat of composite t's accepted CompleteRound under ref that
// differs in its outputs or metrics from the report of t's round.
func (t *task) sameRound(ref store.LeaseRef, end store.RoundEnd) error {
	if !store.SameOutputs(t.pb.Outputs, end.Outputs) {
		return store.ConflictingReport(ref, "outputs")
	}
	rounds := t.job.pb.Rounds
	for i := len(rounds) - 1; i >= 0; i-- {
		if rounds[i].GetRound() == end.Report.GetRound() && !store.SameMetrics(rounds[i], end.Report) {
			return store.ConflictingReport(ref, "metrics")
		}
	}
	return nil
}

// succeed records the success of leased task t.
func (s *Store) succeed(t *task, outputs []*pb.Artifact) {
	s.unlease(t)
	t.pb.State = pb.TaskState_TASK_STATE_SUCCEEDED
	t.pb.Outputs = cloneArtifacts(outputs)
	j := t.job
	j.left--
	j.countSucceeded(t)
	s.place(j)
	j.pb.UpdateTime = timestamppb.New(s.now())
}

func (s *Store) succeedJob(j *job, outputs []*pb.Artifact) {
	j.pb.State = pb.JobState_JOB_STATE_SUCCEEDED
	j.pb.EndTime = timestamppb.New(s.now())
	j.pb.Outputs = cloneArtifacts(outputs)
	s.place(j)
}

func cloneArtifacts(as []*pb.Artifact) []*pb.Artifact {
	out := make([]*pb.Artifact, len(as))
	for i, a := range as {
		out[i] = &pb.Artifact{Name: a.GetName(), Digest: a.GetDigest(), SizeBytes: a.GetSizeBytes()}
	}
	return out
}

// FailTask implements store.Store.
func (s *Store) FailTask(ctx context.Context, ref store.LeaseRef, f store.Failure) (store.Change, error) {
	s.mu.Lock()
	defer s.mu.Unlock()
	t, err := s.held(ref)
	if err != nil {
		return store.Change{}, err
	}
	if f.Permanent() {
		s.unlease(t)
		t.recordFailure(f)
		t.pb.State = pb.TaskState_TASK_STATE_FAILED
		s.end(t.job, pb.JobState_JOB_STATE_FAILED, store.PermanentFailure(t.pb.Id, f.Message), f.Kind)
		return s.change(t, true, false), nil
	}
	return s.failAttempt(t, ref.WorkerID, f), nil
}

// failAttempt counts a transient failed attempt at leased task t by workerID (FailTask,
// a stuck lease): if the failure blames the worker, the worker is blocked from the job at
// BlockAfterFailures; the task goes back after a backoff, or at MaxAttempts fails with its
// job.
func (s *Store) failAttempt(t *task, workerID string, f store.Failure) store.Change {
	j := t.job
	t.failures++
	t.recordFailure(f)
	if f.BlamesWorker() {
		j.failures[workerID]++
		if n := j.failures[workerID]; n >= s.opts.BlockAfterFailures && !blocked(j, workerID) {
			j.pb.BlockedWorkers = append(j.pb.BlockedWorkers, &pb.BlockedWorker{
				WorkerId: workerID, Reason: store.BlockReason(n, f.Message), BlockTime: timestamppb.New(s.now())})
			store.SortBlocked(j.pb.BlockedWorkers)
			j.blockKind = f.Kind
		}
	}
	if t.failures >= s.opts.MaxAttempts {
		return s.failJob(t, t.failures)
	}
	s.delay(t, s.now().Add(s.opts.Backoff(t.failures)))
	return s.change(t, false, false)
}

// recordFailure keeps f's message, kind and log (if it has one) on t.
func (t *task) recordFailure(f store.Failure) {
	t.pb.Error, t.pb.FailureKind = f.Message, f.Kind
	if f.Log != nil {
		t.pb.Log = proto.Clone(f.Log).(*pb.Artifact)
	}
}

// failJob fails t, which failed n times, and its job with t's last error and kind.
func (s *Store) failJob(t *task, n int) store.Change {
	s.unlease(t)
	t.pb.State = pb.TaskState_TASK_STATE_FAILED
	s.end(t.job, pb.JobState_JOB_STATE_FAILED, store.JobFailure(t.pb.Id, n, t.pb.Error), t.pb.FailureKind)
	return s.change(t, true, false)
}

// FailBlockedJob implements store.Store.
func (s *Store) FailBlockedJob(ctx context.Context, jobID string, workers []string) (store.Change, error) {
	s.mu.Lock()
	defer s.mu.Unlock()
	j, err := s.job(jobID)
	if err != nil {
		return store.Change{}, err
	}
	if j.ended() || len(workers) == 0 || slices.ContainsFunc(workers, func(w string) bool { return !blocked(j, w) }) {
		return store.Change{}, nil
	}
	last := j.pb.BlockedWorkers[len(j.pb.BlockedWorkers)-1] // sorted by block time
	s.end(j, pb.JobState_JOB_STATE_FAILED, store.BlockedJobFailure(len(workers), last.Reason), j.blockKind)
	return store.Change{Job: j.snapshot(), JobStateChanged: true}, nil
}

// end moves a job to a terminal state, with why and of what kind of failure for FAILED,
// and cancels its unfinished tasks: those of the current stage and after it, which are of
// the latest round.
func (s *Store) end(j *job, state pb.JobState, message string, kind pb.FailureKind) {
	now := timestamppb.New(s.now())
	j.pb.State = state
	j.pb.Error = message
	j.pb.FailureKind = kind
	j.pb.EndTime = now
	j.pb.UpdateTime = now
	for _, t := range j.tasks[j.cur:] {
		switch t.pb.State {
		case pb.TaskState_TASK_STATE_LEASED:
			s.unlease(t)
			t.pb.State = pb.TaskState_TASK_STATE_CANCELLED
		case pb.TaskState_TASK_STATE_WAITING, pb.TaskState_TASK_STATE_QUEUED:
			t.pb.State = pb.TaskState_TASK_STATE_CANCELLED
		}
	}
	j.returned = nil
	s.place(j)
}

// CancelJob implements store.Store.
func (s *Store) CancelJob(ctx context.Context, jobID string) (store.Change, error) {
	s.mu.Lock()
	defer s.mu.Unlock()
	j, err := s.unended(jobID)
	if err != nil {
		return store.Change{}, err
	}
	s.end(j, pb.JobState_JOB_STATE_CANCELLED, "", pb.FailureKind_FAILURE_KIND_UNSPECIFIED)
	return store.Change{Job: j.snapshot(), JobStateChanged: true}, nil
}

// unended returns a job that has not ended: NotFound or FailedPrecondition otherwise.
func (s *Store) unended(jobID string) (*job, error) {
	j, err := s.job(jobID)
	if err != nil {
		return nil, err
	}
	if j.ended() {
		return nil, errs.E(errs.FailedPrecondition, "job %s has already ended (%s)", jobID, j.pb.State)
	}
	return j, nil
}

// SetJobPriority implements store.Store.
func (s *Store) SetJobPriority(ctx context.Context, jobID string, priority int32) (store.Change, error) {
	if err := store.CheckPriority(priority); err != nil {
		return store.Change{}, err
	}
	s.mu.Lock()
	defer s.mu.Unlock()
	j, err := s.unended(jobID)
	if err != nil {
		return store.Change{}, err
	}
	j.pb.Priority = priority
	j.pb.UpdateTime = timestamppb.New(s.now())
	s.place(j)
	return store.Change{Job: j.snapshot()}, nil
}

// UnblockWorker implements store.Store.
func (s *Store) UnblockWorker(ctx context.Context, jobID, workerID string) (store.Change, error) {
	s.mu.Lock()
	defer s.mu.Unlock()
	j, err := s.job(jobID)
	if err != nil {
		return store.Change{}, err
	}
	n := len(j.pb.BlockedWorkers)
	j.pb.BlockedWorkers = slices.DeleteFunc(j.pb.BlockedWorkers, func(b *pb.BlockedWorker) bool {
		return workerID == "" || b.WorkerId == workerID
	})
	if workerID == "" {
		clear(j.failures)
	} else {
		delete(j.failures, workerID)
	}
	unblocked := len(j.pb.BlockedWorkers) < n
	if unblocked {
		j.pb.UpdateTime = timestamppb.New(s.now())
	}
	return store.Change{Job: j.snapshot(), Queued: unblocked}, nil
}

// PurgeJobs implements store.Store. Nothing here is ever half-made, and deleting a job is
// dropping it from the maps, so budget counts the tasks freed.
func (s *Store) PurgeJobs(ctx context.Context, endedBefore, abandonedBefore time.Time, budget int) (store.Purge, error) {
	s.mu.Lock()
	defer s.mu.Unlock()
	var p store.Purge
	freed := 0
	s.ordered = slices.DeleteFunc(s.ordered, func(j *job) bool {
		if p.More || !j.ended() || !j.pb.EndTime.AsTime().Before(endedBefore) {
			return false
		}
		if freed > 0 && freed+len(j.tasks) > budget {
			p.More = true
			return false
		}
		freed += len(j.tasks)
		s.forget(j)
		p.Deleted = append(p.Deleted, j.pb.Id)
		return true
	})
	return p, nil
}

// forget deletes an ended job but for its place in ordered: its tasks in backoff are
// dropped when due (promote skips ended jobs).
func (s *Store) forget(j *job) {
	delete(s.jobs, j.pb.Id)
	if s.requests[j.request] == j {
		delete(s.requests, j.request)
	}
}

// DeleteJob implements store.Store. Deleting is dropping the job from the maps, so it is
// done at once and leaves PurgeJobs nothing.
func (s *Store) DeleteJob(ctx context.Context, jobID string) (store.Change, error) {
	s.mu.Lock()
	defer s.mu.Unlock()
	j, err := s.job(jobID)
	if err != nil {
		return store.Change{}, err
	}
	cancelled := !j.ended()
	if cancelled {
		s.end(j, pb.JobState_JOB_STATE_CANCELLED, "", pb.FailureKind_FAILURE_KIND_UNSPECIFIED)
	}
	c := store.Change{Job: j.snapshot(), JobStateChanged: cancelled}
	s.forget(j)
	s.ordered = slices.DeleteFunc(s.ordered, func(o *job) bool { return o == j })
	return c, nil
}

// ReopenJob implements store.Store.
func (s *Store) ReopenJob(ctx context.Context, jobID, failedTask string) (store.Change, error) {
	s.mu.Lock()
	defer s.mu.Unlock()
	j, err := s.job(jobID)
	if err != nil {
		return store.Change{}, err
	}
	var t *task
	if failedTask != "" {
		if t = s.task(failedTask); t == nil || t.job != j {
			return store.Change{}, noTask(failedTask)
		}
		if err := store.CheckRetry(failedTask, t.pb.State); err != nil {
			return store.Change{}, err
		}
	}
	if err := store.CheckReopen(jobID, j.pb.State); err != nil {
		return store.Change{}, err
	}
	s.reopen(j)
	c := store.Change{Job: j.snapshot(), JobStateChanged: true, Queued: true}
	if t != nil {
		c.Task = t.snapshot()
	}
	return c, nil
}

// reopen takes an ended job back to its current stage (store package comment,
// Reopening): end left the stage's tasks [cur, end) and those after it cancelled, the
// stage's never-leased range [next, end) unchanged, and its leased-before tasks out of
// returned.
func (s *Store) reopen(j *job) {
	j.pb.State = pb.JobState_JOB_STATE_QUEUED
	j.pb.Error, j.pb.FailureKind, j.pb.EndTime = "", pb.FailureKind_FAILURE_KIND_UNSPECIFIED, nil
	j.pb.UpdateTime = timestamppb.New(s.now())
	j.returned = j.returned[:0]
	for i := j.cur; i < len(j.tasks); i++ {
		t := j.tasks[i]
		if t.pb.State == pb.TaskState_TASK_STATE_SUCCEEDED {
			continue
		}
		t.failures, t.expiries = 0, 0
		t.pb.RetryTime, t.retryAt, t.pb.WorkerId = nil, time.Time{}, ""
		if i >= j.end {
			t.pb.State = pb.TaskState_TASK_STATE_WAITING
			continue
		}
		t.pb.State = pb.TaskState_TASK_STATE_QUEUED
		if i < j.next {
			heap.Push(&j.returned, i)
		}
	}
	// Its tasks still in the delay queue are queued now: promote must not queue them twice.
	s.delayed = slices.DeleteFunc(s.delayed, func(t *task) bool { return t.job == j })
	heap.Init(&s.delayed)
	s.place(j)
}
