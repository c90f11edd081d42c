package memstore

import (
	"context"
	"fmt"
	"slices"
	"time"

	"google.golang.org/protobuf/proto"
	"google.golang.org/protobuf/types/known/timestamppb"

	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// LeaseTask implements store.Store: the lowest leasable task of phases in the job of
// highest priority, then fewest leases held, then oldest, that has not blocked workerID.
// Held leases are counted on the way rather than kept, like everything here, by a scan.
func (s *Store) LeaseTask(ctx context.Context, workerID string, phases []pb.Phase) (*store.Leased, error) {
	if err := store.CheckLeaseArgs(workerID, phases); err != nil {
		return nil, err
	}
	s.mu.Lock()
	defer s.mu.Unlock()
	now := s.now()
	var t *task
	bestHeld := 0
	for _, j := range s.ordered { // oldest first, so a tie keeps the older job
		if store.Ended(j.pb.State) || blocked(j, workerID) {
			continue
		}
		held := 0
		var first *task
		for _, o := range j.tasks {
			if o.pb.State == pb.TaskState_TASK_STATE_LEASED {
				held++
			} else if first == nil && o.leasable(phases, now) {
				first = o
			}
		}
		if first == nil {
			continue
		}
		if p := j.pb.Priority; t == nil || p > t.job.pb.Priority || (p == t.job.pb.Priority && held < bestHeld) {
			t, bestHeld = first, held
		}
	}
	if t == nil {
		return nil, nil
	}
	j := t.job
	t.epoch++
	t.expire = now.Add(s.opts.LeaseDuration)
	t.progress, t.progressAt = 0, now
	t.pb.State = pb.TaskState_TASK_STATE_LEASED
	t.pb.WorkerId = workerID
	t.pb.Attempts++
	t.pb.RetryTime = nil
	started := j.pb.State == pb.JobState_JOB_STATE_QUEUED
	if started {
		j.pb.State = pb.JobState_JOB_STATE_RUNNING
	}
	j.pb.UpdateTime = timestamppb.New(now)
	return &store.Leased{
		Lease:       &pb.Lease{TaskId: t.pb.Id, Epoch: t.epoch, ExpireTime: timestamppb.New(t.expire)},
		Task:        t.snapshot(),
		SceneDigest: j.pb.SceneDigest,
		Change:      s.change(t, started, false),
	}, nil
}

// leasable: queued, of one of phases, and out of its backoff.
func (t *task) leasable(phases []pb.Phase, now time.Time) bool {
	return t.pb.State == pb.TaskState_TASK_STATE_QUEUED && slices.Contains(phases, t.pb.Phase) &&
		(t.pb.RetryTime == nil || !now.Before(t.pb.RetryTime.AsTime()))
}

func blocked(j *job, workerID string) bool {
	return slices.ContainsFunc(j.pb.BlockedWorkers, func(b *pb.BlockedWorker) bool { return b.WorkerId == workerID })
}

// held returns the task ref names if ref's lease on it is still valid.
func (s *Store) held(ref store.LeaseRef) (*task, error) {
	t := s.tasks[ref.TaskID]
	if t == nil {
		return nil, &errs.Error{Kind: errs.NotFound, Field: "task_id", Message: fmt.Sprintf("no task %q", ref.TaskID)}
	}
	switch {
	case t.epoch != ref.Epoch:
		return nil, errs.E(errs.FailedPrecondition, "task %s: lease epoch %d is retired (current epoch %d)", ref.TaskID, ref.Epoch, t.epoch)
	case t.pb.WorkerId != ref.WorkerID:
		return nil, errs.E(errs.FailedPrecondition, "task %s: lease epoch %d is held by another worker, not %s", ref.TaskID, ref.Epoch, ref.WorkerID)
	case t.pb.State != pb.TaskState_TASK_STATE_LEASED:
		return nil, errs.E(errs.FailedPrecondition, "task %s: lease epoch %d is no longer held (task is %s)", ref.TaskID, ref.Epoch, t.pb.State)
	case !s.now().Before(t.expire):
		return nil, errs.E(errs.FailedPrecondition, "task %s: lease epoch %d expired at %s", ref.TaskID, ref.Epoch, t.expire.UTC().Format("15:04:05.000"))
	}
	return t, nil
}

// requeue puts a leased task back in the queue.
func (s *Store) requeue(t *task) {
	t.pb.State = pb.TaskState_TASK_STATE_QUEUED
	t.pb.WorkerId = ""
	t.job.pb.UpdateTime = timestamppb.New(s.now())
}

// ExtendLeases implements store.Store.
func (s *Store) ExtendLeases(ctx context.Context, workerID string, held []*pb.HeldLease) (store.Heartbeat, error) {
	s.mu.Lock()
	defer s.mu.Unlock()
	var hb store.Heartbeat
	now := s.now()
	for _, h := range held {
		t, err := s.held(store.LeaseRef{WorkerID: workerID, TaskID: h.GetTaskId(), Epoch: h.GetEpoch()})
		revoke := err != nil
		switch {
		case revoke:
		case h.GetProgress() > t.progress:
			t.progress, t.progressAt = h.GetProgress(), now
		case !store.Exempt(t.pb.Phase) && now.Sub(t.progressAt) >= s.opts.StuckTimeout:
			revoke = true
			hb.Changes = append(hb.Changes, s.failAttempt(t, workerID, store.Transient(s.opts.StuckMessage())))
		}
		if revoke {
			hb.Revoked = append(hb.Revoked, &pb.HeldLease{TaskId: h.GetTaskId(), Epoch: h.GetEpoch()})
			continue
		}
		t.expire = now.Add(s.opts.LeaseDuration)
		hb.Extended = append(hb.Extended, &pb.Lease{TaskId: t.pb.Id, Epoch: t.epoch, ExpireTime: timestamppb.New(t.expire)})
	}
	return hb, nil
}

// ExpireLeases implements store.Store.
func (s *Store) ExpireLeases(ctx context.Context) ([]store.Change, error) {
	s.mu.Lock()
	defer s.mu.Unlock()
	now := s.now()
	var changes []store.Change
	for _, j := range s.ordered {
		for _, t := range j.tasks {
			// Ending the job cancels its other leases, so the state is checked per task.
			if t.pb.State != pb.TaskState_TASK_STATE_LEASED || now.Before(t.expire) {
				continue
			}
			t.expiries++
			t.pb.Error, t.pb.FailureKind = store.ExpiredMessage, pb.FailureKind_FAILURE_KIND_TRANSIENT
			if t.expiries >= s.opts.MaxExpiries {
				changes = append(changes, s.failJob(t, t.expiries))
				continue
			}
			s.requeue(t)
			changes = append(changes, s.change(t, false, true))
		}
	}
	return changes, nil
}

// CompleteTask implements store.Store.
func (s *Store) CompleteTask(ctx context.Context, ref store.LeaseRef, outputs []*pb.Artifact) (store.Change, error) {
	s.mu.Lock()
	defer s.mu.Unlock()
	if s.repeated(ref) {
		return store.Change{}, nil // a repeated report that was accepted
	}
	t, err := s.held(ref)
	if err != nil {
		return store.Change{}, err
	}
	s.succeed(t, outputs)
	j := t.job

	// Open the next stage once every task of this one has succeeded.
	stage := store.Stage(t.pb)
	var next []*task
	for _, o := range j.tasks {
		os := store.Stage(o.pb)
		if os == stage && o.pb.State != pb.TaskState_TASK_STATE_SUCCEEDED {
			return s.change(t, false, false), nil
		}
		if os > stage && (len(next) == 0 || store.Stage(next[0].pb) == os) {
			next = append(next, o)
		}
	}
	if len(next) > 0 {
		for _, o := range next {
			o.pb.State = pb.TaskState_TASK_STATE_QUEUED
		}
		return s.change(t, false, true), nil
	}
	// That was the last stage: the job succeeded with its outputs.
	var final []*pb.Artifact
	for _, o := range j.tasks {
		if store.Stage(o.pb) == stage {
			final = append(final, o.pb.Outputs...)
		}
	}
	s.succeedJob(j, final)
	return s.change(t, true, false), nil
}

// CompleteRound implements store.Store.
func (s *Store) CompleteRound(ctx context.Context, ref store.LeaseRef, end store.RoundEnd) (store.Change, error) {
	if end.Report == nil {
		return store.Change{}, errs.E(errs.Internal, "CompleteRound needs the round's report")
	}
	s.mu.Lock()
	defer s.mu.Unlock()
	if s.repeated(ref) {
		return store.Change{}, nil
	}
	t, err := s.held(ref)
	if err != nil {
		return store.Change{}, err
	}
	j := t.job
	stage := store.Stage(t.pb)
	for _, o := range j.tasks {
		if o != t && store.Stage(o.pb) >= stage {
			return store.Change{}, errs.E(errs.Internal, "task %s is not the last task of its round", t.pb.Id)
		}
	}
	if err := store.CheckPlan(end.Next); err != nil {
		return store.Change{}, errs.Wrap(errs.Internal, err, "next round")
	}
	if len(end.Next) > 0 && store.Stage(end.Next[0]) <= stage {
		return store.Change{}, errs.E(errs.Internal, "next round's task 0 is out of order")
	}
	s.succeed(t, end.Outputs)
	j.pb.Rounds = append(j.pb.Rounds, proto.Clone(end.Report).(*pb.RoundReport))
	if len(end.Next) > 0 {
		s.appendTasks(j, end.Next)
		return s.change(t, false, true), nil
	}
	s.succeedJob(j, end.Final)
	return s.change(t, true, false), nil
}

// repeated reports whether ref names a task that already succeeded under that lease.
func (s *Store) repeated(ref store.LeaseRef) bool {
	t := s.tasks[ref.TaskID]
	return t != nil && t.pb.State == pb.TaskState_TASK_STATE_SUCCEEDED && t.epoch == ref.Epoch && t.pb.WorkerId == ref.WorkerID
}

func (s *Store) succeed(t *task, outputs []*pb.Artifact) {
	t.pb.State = pb.TaskState_TASK_STATE_SUCCEEDED
	t.pb.Outputs = cloneArtifacts(outputs)
	t.job.pb.UpdateTime = timestamppb.New(s.now())
}

func (s *Store) succeedJob(j *job, outputs []*pb.Artifact) {
	j.pb.State = pb.JobState_JOB_STATE_SUCCEEDED
	j.pb.EndTime = timestamppb.New(s.now())
	j.pb.Outputs = cloneArtifacts(outputs)
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
		t.pb.Error, t.pb.FailureKind = f.Message, f.Kind
		t.pb.State = pb.TaskState_TASK_STATE_FAILED
		s.end(t.job, pb.JobState_JOB_STATE_FAILED, store.PermanentFailure(t.pb.Id, f.Message), f.Kind)
		return s.change(t, true, false), nil
	}
	return s.failAttempt(t, ref.WorkerID, f), nil
}

// failAttempt counts a transient failed attempt at leased task t by workerID (FailTask,
// a stuck lease): if the failure blames the worker, it is blocked from the job at
// BlockAfterFailures; the task goes
// back after a backoff, or at MaxAttempts fails with its job.
func (s *Store) failAttempt(t *task, workerID string, f store.Failure) store.Change {
	j := t.job
	t.failures++
	t.pb.Error, t.pb.FailureKind = f.Message, f.Kind
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
	s.requeue(t)
	t.pb.RetryTime = timestamppb.New(s.now().Add(s.opts.Backoff(t.failures)))
	return s.change(t, false, false)
}

// failJob fails t, which failed n times, and its job with t's last error and kind.
func (s *Store) failJob(t *task, n int) store.Change {
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
	if store.Ended(j.pb.State) || len(workers) == 0 || slices.ContainsFunc(workers, func(w string) bool { return !blocked(j, w) }) {
		return store.Change{}, nil
	}
	last := j.pb.BlockedWorkers[len(j.pb.BlockedWorkers)-1] // sorted by block time
	s.end(j, pb.JobState_JOB_STATE_FAILED, store.BlockedJobFailure(len(workers), last.Reason), j.blockKind)
	return store.Change{Job: j.snapshot(), JobStateChanged: true}, nil
}

// end moves a job to a terminal state, with why and of what kind of failure for FAILED,
// and cancels its unfinished tasks.
func (s *Store) end(j *job, state pb.JobState, message string, kind pb.FailureKind) {
	now := timestamppb.New(s.now())
	j.pb.State = state
	j.pb.Error = message
	j.pb.FailureKind = kind
	j.pb.EndTime = now
	j.pb.UpdateTime = now
	for _, t := range j.tasks {
		switch t.pb.State {
		case pb.TaskState_TASK_STATE_WAITING, pb.TaskState_TASK_STATE_QUEUED, pb.TaskState_TASK_STATE_LEASED:
			t.pb.State = pb.TaskState_TASK_STATE_CANCELLED
		}
	}
}

// ReleaseTask implements store.Store.
func (s *Store) ReleaseTask(ctx context.Context, ref store.LeaseRef) (store.Change, error) {
	s.mu.Lock()
	defer s.mu.Unlock()
	t, err := s.held(ref)
	if err != nil {
		return store.Change{}, err
	}
	s.requeue(t)
	return s.change(t, false, true), nil
}

// ReleaseWorker implements store.Store.
func (s *Store) ReleaseWorker(ctx context.Context, workerID string) ([]store.Change, error) {
	s.mu.Lock()
	defer s.mu.Unlock()
	var changes []store.Change
	for _, j := range s.ordered {
		for _, t := range j.tasks {
			if t.pb.State == pb.TaskState_TASK_STATE_LEASED && t.pb.WorkerId == workerID {
				s.requeue(t)
				changes = append(changes, s.change(t, false, true))
			}
		}
	}
	return changes, nil
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
	if store.Ended(j.pb.State) {
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
