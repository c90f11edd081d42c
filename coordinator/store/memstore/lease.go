package memstore

import (
	"context"
	"fmt"
	"slices"

	"google.golang.org/protobuf/proto"
	"google.golang.org/protobuf/types/known/timestamppb"

	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// LeaseTask implements store.Store: the first queued task of phases in the oldest job
// with one.
func (s *Store) LeaseTask(ctx context.Context, workerID string, phases []pb.Phase) (*store.Leased, error) {
	if err := store.CheckLeaseArgs(workerID, phases); err != nil {
		return nil, err
	}
	s.mu.Lock()
	defer s.mu.Unlock()
	for _, j := range s.ordered {
		if store.Ended(j.pb.State) {
			continue
		}
		for _, t := range j.tasks {
			if t.pb.State != pb.TaskState_TASK_STATE_QUEUED || !slices.Contains(phases, t.pb.Phase) {
				continue
			}
			now := s.now()
			t.epoch++
			t.expire = now.Add(s.opts.LeaseDuration)
			t.pb.State = pb.TaskState_TASK_STATE_LEASED
			t.pb.WorkerId = workerID
			t.pb.Attempts++
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
	}
	return nil, nil
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
func (s *Store) ExtendLeases(ctx context.Context, workerID string, held []*pb.HeldLease) ([]*pb.Lease, []*pb.HeldLease, error) {
	s.mu.Lock()
	defer s.mu.Unlock()
	var extended []*pb.Lease
	var revoked []*pb.HeldLease
	for _, h := range held {
		t, err := s.held(store.LeaseRef{WorkerID: workerID, TaskID: h.GetTaskId(), Epoch: h.GetEpoch()})
		if err != nil {
			revoked = append(revoked, &pb.HeldLease{TaskId: h.GetTaskId(), Epoch: h.GetEpoch()})
			continue
		}
		t.expire = s.now().Add(s.opts.LeaseDuration)
		extended = append(extended, &pb.Lease{TaskId: t.pb.Id, Epoch: t.epoch, ExpireTime: timestamppb.New(t.expire)})
	}
	return extended, revoked, nil
}

// ExpireLeases implements store.Store.
func (s *Store) ExpireLeases(ctx context.Context) ([]store.Change, error) {
	s.mu.Lock()
	defer s.mu.Unlock()
	now := s.now()
	var changes []store.Change
	for _, j := range s.ordered {
		if store.Ended(j.pb.State) {
			continue
		}
		for _, t := range j.tasks {
			if t.pb.State == pb.TaskState_TASK_STATE_LEASED && !now.Before(t.expire) {
				s.requeue(t)
				changes = append(changes, s.change(t, false, true))
			}
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
	for i, n := range end.Next {
		if n.GetIndex() != uint32(i) || (i > 0 && store.Stage(n) < store.Stage(end.Next[i-1])) || store.Stage(n) <= stage {
			return store.Change{}, errs.E(errs.Internal, "next round's task %d is out of order", i)
		}
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
func (s *Store) FailTask(ctx context.Context, ref store.LeaseRef, message string) (store.Change, error) {
	s.mu.Lock()
	defer s.mu.Unlock()
	t, err := s.held(ref)
	if err != nil {
		return store.Change{}, err
	}
	t.failures++
	t.pb.Error = message
	if t.failures < s.opts.MaxAttempts {
		s.requeue(t)
		return s.change(t, false, true), nil
	}
	t.pb.State = pb.TaskState_TASK_STATE_FAILED
	s.end(t.job, pb.JobState_JOB_STATE_FAILED,
		fmt.Sprintf("task %s failed %d times; last error: %s", t.pb.Id, t.failures, message))
	return s.change(t, true, false), nil
}

// end moves a job to a terminal state and cancels its unfinished tasks.
func (s *Store) end(j *job, state pb.JobState, message string) {
	now := timestamppb.New(s.now())
	j.pb.State = state
	j.pb.Error = message
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
	j, err := s.job(jobID)
	if err != nil {
		return store.Change{}, err
	}
	if store.Ended(j.pb.State) {
		return store.Change{}, errs.E(errs.FailedPrecondition, "job %s has already ended (%s)", jobID, j.pb.State)
	}
	s.end(j, pb.JobState_JOB_STATE_CANCELLED, "")
	return store.Change{Job: j.snapshot(), JobStateChanged: true}, nil
}
