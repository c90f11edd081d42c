package service

import (
	"context"
	"errors"
	"fmt"
	"slices"
	"time"

	"photonfarm/contract/rules"
	"photonfarm/contract/tasks"
	"photonfarm/coordinator/blobstore"
	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// The task operations behind WorkerService, as Go methods: the gRPC handlers call them for
// workers, and the coordinator's builder calls them directly, so that its leases go through
// the same store with the same epochs and expiry as any worker's.

// Lease leases to workerID the next queued task of one of phases, waiting up to wait for
// one (0: do not wait). It returns a response without a lease when there is nothing to do,
// the wait ran out, or the coordinator is shutting down. The task's spec is filled in
// (composite tiles, build shards, a tile's photon snapshot).
func (s *Service) Lease(ctx context.Context, workerID string, phases []pb.Phase, wait time.Duration) (*pb.LeaseTaskResponse, error) {
	var timeout <-chan time.Time
	if wait > 0 {
		t := time.NewTimer(wait)
		defer t.Stop()
		timeout = t.C
	}
	for {
		wake := s.queued.wait()
		l, err := s.cfg.Store.LeaseTask(ctx, workerID, phases)
		if err != nil {
			return nil, err
		}
		if l != nil {
			resp, err := s.granted(ctx, workerID, l)
			if resp != nil || err != nil {
				return resp, err
			}
			continue // the task's input was lost and its job failed: lease another
		}
		if wait == 0 {
			return &pb.LeaseTaskResponse{}, nil
		}
		retry, stop := s.retryTimer()
		select {
		case <-wake:
		case <-retry:
		case <-timeout:
			return &pb.LeaseTaskResponse{}, nil
		case <-s.done:
			return &pb.LeaseTaskResponse{}, nil
		case <-ctx.Done():
			return nil, ctx.Err()
		}
		stop()
	}
}

// retryTimer fires when the earliest known backoff ends (never if none is known); stop
// releases it.
func (s *Service) retryTimer() (<-chan time.Time, func() bool) {
	now := s.cfg.Clock.Now()
	at := s.retries.next(now)
	if at.IsZero() {
		return nil, func() bool { return false }
	}
	t := time.NewTimer(at.Sub(now))
	return t.C, t.Stop
}

// granted completes a lease by filling in what the task needs from earlier phases and
// checking that the blobs it reads are there. If one is lost (missing or damaged), the task
// and its job fail (failLostInput) and granted returns neither a lease nor an error; if
// anything else fails, the lease is handed back rather than left to expire.
func (s *Service) granted(ctx context.Context, workerID string, l *store.Leased) (*pb.LeaseTaskResponse, error) {
	s.publish(l.Change)
	err := s.fillSpec(ctx, l)
	if err == nil {
		err = s.checkInputs(ctx, l)
	}
	if err != nil {
		ref := store.LeaseRef{WorkerID: workerID, TaskID: l.Lease.GetTaskId(), Epoch: l.Lease.GetEpoch()}
		if li := (*blobstore.LostError)(nil); errors.As(err, &li) {
			return nil, s.failLostInput(ctx, ref, li)
		}
		if c, rerr := s.cfg.Store.ReleaseTask(ctx, ref); rerr == nil {
			s.publish(c)
		}
		return nil, err
	}
	s.mirror(ctx, "a lease", func(ctx context.Context) error { return s.workers.Leased(ctx, workerID, l.Lease.GetTaskId()) })
	s.cfg.Metrics.LeaseGranted(l.Task.GetPhase())
	s.log.Debug("task leased", "task", l.Task.GetId(), "worker", workerID, "epoch", l.Lease.GetEpoch(), "attempt", l.Task.GetAttempts())
	return &pb.LeaseTaskResponse{Lease: l.Lease, Task: l.Task, SceneDigest: l.SceneDigest}, nil
}

// Extend extends the leases workerID still holds among held; the others are revoked,
// among them stuck ones (no progress for the store's StuckTimeout), which count as failed
// attempts.
func (s *Service) Extend(ctx context.Context, workerID string, held []*pb.HeldLease) ([]*pb.Lease, []*pb.HeldLease, error) {
	hb, err := s.cfg.Store.ExtendLeases(ctx, workerID, held)
	if err != nil {
		return nil, nil, err
	}
	for _, c := range hb.Changes {
		s.mirror(ctx, "a stuck lease", func(ctx context.Context) error { return s.workers.Ended(ctx, workerID, c.Task.GetId(), false) })
		s.cfg.Metrics.TaskFailed()
		s.log.Warn("task failed", "task", c.Task.GetId(), "job", c.Job.GetId(), "worker", workerID, "error", c.Task.GetError())
		s.publish(c)
		if err := s.failIfEveryWorkerBlocked(ctx, c, workerID); err != nil {
			return nil, nil, err
		}
	}
	for _, r := range hb.Revoked {
		s.mirror(ctx, "a revoked lease", func(ctx context.Context) error { return s.workers.Dropped(ctx, workerID, r.GetTaskId()) })
	}
	return hb.Extended, hb.Revoked, nil
}

// Complete records a task's success with its outputs, which must name blobs in the blob
// store with their true sizes. Each is touched (blobstore.Touch) before it is recorded,
// so that the collector of unreferenced blobs keeps it.
func (s *Service) Complete(ctx context.Context, ref store.LeaseRef, outputs []*pb.Artifact) error {
	return s.CompleteWithMetrics(ctx, ref, outputs, nil)
}

// CompleteWithMetrics is Complete with a composite's error metrics. The composite of a
// round ends it: the round's report is recorded and the job goes on to the next round or
// stops (StopReason), in one store step (store.Store.CompleteRound).
func (s *Service) CompleteWithMetrics(ctx context.Context, ref store.LeaseRef, outputs []*pb.Artifact, metrics *pb.RoundMetrics) error {
	// Whatever the store says (a report under a lease lost to a cancel is refused), the
	// worker has stopped working on the task.
	defer s.dropped(ctx, ref)
	if metrics == nil {
		metrics = &pb.RoundMetrics{}
	}
	if err := checkMetrics(metrics); err != nil {
		return err
	}
	for i, a := range outputs {
		if err := s.checkArtifact(ctx, fmt.Sprintf("outputs[%d]", i), a); err != nil {
			return err
		}
	}
	task, err := s.cfg.Store.GetTask(ctx, ref.TaskID)
	if err != nil {
		return err
	}
	var c store.Change
	if task.GetComposite() != nil {
		end, why, err := s.roundEnd(ctx, task, outputs, metrics)
		if li := (*blobstore.LostError)(nil); errors.As(err, &li) {
			if err := s.failLostInput(ctx, ref, li); err != nil {
				return err
			}
			return errs.E(errs.FailedPrecondition, "the job failed instead: %v", li)
		}
		if err != nil {
			return err
		}
		if c, err = s.cfg.Store.CompleteRound(ctx, ref, end); err != nil {
			return err
		}
		if c.Job != nil {
			r := end.Report
			attrs := []any{"job", task.GetJobId(), "round", r.GetRound(), "elapsed_s", r.GetElapsedSeconds(), "stop", why}
			// Unset estimates are left out: slog would print the pointers.
			if r.ErrorEstimate != nil {
				attrs = append(attrs, "error_estimate", r.GetErrorEstimate())
			}
			if r.ErrorEstimateLow != nil && r.ErrorEstimateHigh != nil {
				attrs = append(attrs, "error_estimate_low", r.GetErrorEstimateLow(), "error_estimate_high", r.GetErrorEstimateHigh())
			}
			if r.ReferenceRmse != nil {
				attrs = append(attrs, "reference_rmse", r.GetReferenceRmse())
			}
			s.log.Info("round finished", attrs...)
		}
	} else if c, err = s.cfg.Store.CompleteTask(ctx, ref, outputs); err != nil {
		return err
	}
	if c.Task != nil {
		s.mirror(ctx, "a completion", func(ctx context.Context) error { return s.workers.Ended(ctx, ref.WorkerID, ref.TaskID, true) })
		s.cfg.Metrics.TaskCompleted(c.Task.GetPhase())
		s.log.Debug("task completed", "task", ref.TaskID, "worker", ref.WorkerID, "epoch", ref.Epoch)
	}
	s.publish(c)
	return nil
}

// taskLogName is the name of a task's log among its outputs and in FailTaskRequest.log.
var taskLogName = tasks.ArtifactName(pb.ArtifactKind_ARTIFACT_KIND_TASK_LOG)

// checkArtifact checks artifact a of a report, at field path p: a name, a digest that
// names a stored blob of its size_bytes, and for a task log ("task.log") at most the
// contract's max_task_log_bytes. The blob is touched (blobstore.Touch), so that the
// collector of unreferenced blobs keeps it until the report is recorded.
func (s *Service) checkArtifact(ctx context.Context, p string, a *pb.Artifact) error {
	if a.GetName() == "" || len(a.GetName()) > 255 {
		return errs.Field(p+".name", "must be 1 to 255 bytes, got %d", len(a.GetName()))
	}
	if !rules.ValidDigest(a.GetDigest()) {
		return errs.Field(p+".digest", "must be \"sha256:\" followed by 64 lowercase hex digits, got %q", a.GetDigest())
	}
	if max := int64(rules.RPC.GetMaxTaskLogBytes()); a.GetName() == taskLogName && a.GetSizeBytes() > max {
		return errs.Field(p+".size_bytes", "a task log must be at most %d bytes (max_task_log_bytes), got %d", max, a.GetSizeBytes())
	}
	info, err := s.cfg.Blobs.Touch(ctx, a.GetDigest())
	if errs.Is(err, errs.NotFound) {
		return errs.Field(p+".digest", "no blob %s; upload it before reporting the task", a.GetDigest())
	}
	if err != nil {
		return err
	}
	if info.Size != a.GetSizeBytes() {
		return errs.Field(p+".size_bytes", "blob %s has %d bytes, not %d", a.GetDigest(), info.Size, a.GetSizeBytes())
	}
	return nil
}

// Fail records a task's failure; its message is truncated to the contract's
// max_error_bytes, and its log, if any, is checked as outputs are (checkArtifact). A permanent kind fails the job at once; a transient one (or none, or
// one this coordinator does not know, from a newer worker) is retried, and if it blocks the worker from the job and every worker is then blocked,
// the job fails (failIfEveryWorkerBlocked).
func (s *Service) Fail(ctx context.Context, ref store.LeaseRef, f store.Failure) error {
	defer s.dropped(ctx, ref)
	if f.Message == "" {
		return errs.Field("error", "must say why the task failed")
	}
	f.Message = rules.Truncate(f.Message, int(rules.RPC.GetMaxErrorBytes()))
	if f.Log != nil {
		if f.Log.GetName() != taskLogName {
			return errs.Field("log.name", "must be %q, got %q", taskLogName, f.Log.GetName())
		}
		if err := s.checkArtifact(ctx, "log", f.Log); err != nil {
			return err
		}
	}
	c, err := s.cfg.Store.FailTask(ctx, ref, f)
	if err != nil {
		return err
	}
	s.mirror(ctx, "a failure", func(ctx context.Context) error { return s.workers.Ended(ctx, ref.WorkerID, ref.TaskID, false) })
	s.cfg.Metrics.TaskFailed()
	s.log.Warn("task failed", "task", ref.TaskID, "job", c.Job.GetId(), "worker", ref.WorkerID, "epoch", ref.Epoch,
		"kind", tasks.FailureOf(f.Kind).Label, "permanent", f.Permanent(), "error", f.Message)
	s.publish(c)
	return s.failIfEveryWorkerBlocked(ctx, c, ref.WorkerID)
}

// Release queues a leased task again without counting a failure.
func (s *Service) Release(ctx context.Context, ref store.LeaseRef) error {
	defer s.dropped(ctx, ref)
	c, err := s.cfg.Store.ReleaseTask(ctx, ref)
	if err != nil {
		return err
	}
	s.publish(c)
	return nil
}

// failIfEveryWorkerBlocked fails c's job when the failure c records has blocked workerID
// from it and every eligible worker is now blocked: the job would otherwise wait for
// ever (FailBlockedJobs checks again later, for workers lost since). Eligible are the workers this coordinator knows, registered and not lost, that
// lease the phase of c's task (every worker leases every worker phase, so all of them
// for a worker phase; the builder's phases have no workers to run out of).
func (s *Service) failIfEveryWorkerBlocked(ctx context.Context, c store.Change, workerID string) error {
	job := c.Job
	if job == nil || store.Ended(job.GetState()) || !slices.ContainsFunc(job.GetBlockedWorkers(), func(b *pb.BlockedWorker) bool {
		return b.GetWorkerId() == workerID
	}) {
		return nil
	}
	if ph, ok := tasks.Phases.Of(c.Task.GetPhase()); !ok || ph.Executor != pb.Executor_EXECUTOR_WORKER {
		return nil
	}
	live, err := s.workers.Live(ctx, s.cfg.Clock.Now(), s.cfg.LeaseDuration)
	if err != nil {
		return err
	}
	return s.failBlockedJob(ctx, job.GetId(), live)
}
