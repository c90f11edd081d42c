package memstore

import (
	"cmp"
	"container/heap"
	"context"
	"slices"
	"time"

	"google.golang.org/protobuf/types/known/timestamppb"

	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// LeaseTask implements store.Store: the lowest leasable task of phases in the job of
// highest priority, then fewest leases held, then oldest, that has not blocked workerID,
// read off the heads of the ready queues (queue.go).
func (s *Store) LeaseTask(ctx context.Context, workerID string, phases []pb.Phase) (*store.Leased, error) {
	if err := store.CheckLeaseArgs(workerID, phases); err != nil {
		return nil, err
	}
	s.mu.Lock()
	defer s.mu.Unlock()
	now := s.now()
	s.promote(now)
	var j *job
	for _, p := range phases {
		if h := s.head(p, workerID); h != nil && (j == nil || before(h, j)) {
			j = h
		}
	}
	if j == nil {
		return nil, nil
	}
	var t *task
	if len(j.returned) > 0 {
		t = j.tasks[heap.Pop(&j.returned).(int)]
	} else {
		t = j.tasks[j.next]
		j.next++
	}
	t.epoch++
	t.expire = now.Add(s.opts.LeaseDuration)
	t.progress, t.progressAt = 0, now
	t.pb.State = pb.TaskState_TASK_STATE_LEASED
	t.pb.WorkerId = workerID
	t.pb.Attempts++
	t.pb.RetryTime = nil
	s.leases[t] = struct{}{}
	j.held++
	s.place(j)
	started := j.pb.State == pb.JobState_JOB_STATE_QUEUED
	if started {
		j.pb.State = pb.JobState_JOB_STATE_RUNNING
	}
	j.pb.UpdateTime = timestamppb.New(now)
	return &store.Leased{
		Lease:       &pb.Lease{TaskId: t.pb.Id, Epoch: t.epoch, ExpireTime: timestamppb.New(t.expire)},
		Task:        t.snapshot(),
		SceneDigest: j.pb.SceneDigest,
		StageStart:  uint32(j.cur),
		StageEnd:    uint32(j.end),
		Change:      s.change(t, started, false),
	}, nil
}

// promote queues again the tasks whose backoff has ended.
func (s *Store) promote(now time.Time) {
	for len(s.delayed) > 0 && !now.Before(s.delayed[0].retryAt) {
		t := heap.Pop(&s.delayed).(*task)
		if t.job.ended() || t.pb.State != pb.TaskState_TASK_STATE_QUEUED {
			continue
		}
		heap.Push(&t.job.returned, int(t.pb.Index))
		s.place(t.job)
	}
}

func blocked(j *job, workerID string) bool {
	return slices.ContainsFunc(j.pb.BlockedWorkers, func(b *pb.BlockedWorker) bool { return b.WorkerId == workerID })
}

// held returns the task ref names if ref's lease on it is still valid.
func (s *Store) held(ref store.LeaseRef) (*task, error) {
	t := s.task(ref.TaskID)
	if t == nil {
		return nil, noTask(ref.TaskID)
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

// unlease ends t's lease: it is no longer held, and its job holds one lease less.
func (s *Store) unlease(t *task) {
	delete(s.leases, t)
	t.job.held--
}

// requeue puts a leased task back in its job's queue.
func (s *Store) requeue(t *task) {
	s.unlease(t)
	t.pb.State = pb.TaskState_TASK_STATE_QUEUED
	t.pb.WorkerId = ""
	heap.Push(&t.job.returned, int(t.pb.Index))
	s.place(t.job)
	t.job.pb.UpdateTime = timestamppb.New(s.now())
}

// delay puts a leased task back to be leased at retry.
func (s *Store) delay(t *task, retry time.Time) {
	s.unlease(t)
	t.pb.State = pb.TaskState_TASK_STATE_QUEUED
	t.pb.WorkerId = ""
	t.pb.RetryTime = timestamppb.New(retry)
	t.retryAt = retry
	heap.Push(&s.delayed, t)
	s.place(t.job)
	t.job.pb.UpdateTime = timestamppb.New(s.now())
}

// leased returns the tasks leased now that keep, by lease expiry then task id (the order
// the Redis store keeps its leases in).
func (s *Store) leased(keep func(*task) bool) []*task {
	var out []*task
	for t := range s.leases {
		if keep(t) {
			out = append(out, t)
		}
	}
	slices.SortFunc(out, func(a, b *task) int {
		return cmp.Or(a.expire.Compare(b.expire), cmp.Compare(a.pb.Id, b.pb.Id))
	})
	return out
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
	for _, t := range s.leased(func(t *task) bool { return !now.Before(t.expire) }) {
		// Ending the job cancels its other leases, so the state is checked per task.
		if t.pb.State != pb.TaskState_TASK_STATE_LEASED {
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
	return changes, nil
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
	for _, t := range s.leased(func(t *task) bool { return t.pb.WorkerId == workerID }) {
		s.requeue(t)
		changes = append(changes, s.change(t, false, true))
	}
	return changes, nil
}
