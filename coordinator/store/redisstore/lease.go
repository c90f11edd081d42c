package redisstore

import (
	"context"
	"fmt"
	"strconv"
	"strings"

	"google.golang.org/protobuf/proto"
	"google.golang.org/protobuf/types/known/timestamppb"

	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// LeaseTask implements store.Store (scheduling: scripts.go).
func (s *Store) LeaseTask(ctx context.Context, workerID string, phases []pb.Phase) (*store.Leased, error) {
	if err := store.CheckLeaseArgs(workerID, phases); err != nil {
		return nil, err
	}
	args := []any{workerID, micros(s.opts.Clock.Now().Add(s.opts.LeaseDuration))}
	for _, p := range phases {
		args = append(args, int32(p))
	}
	r, err := s.change(ctx, leaseScript, args...)
	if err != nil || r.none {
		return nil, err
	}
	return &store.Leased{
		Lease: &pb.Lease{TaskId: r.change.Task.Id, Epoch: number(r.task["epoch"]), ExpireTime: timestamp(r.task["expire"])},
		// A copy: the service fills the spec of Task in place while Change is being
		// published to watchers, who must not see it half-written.
		Task:        proto.Clone(r.change.Task).(*pb.Task),
		SceneDigest: r.change.Job.SceneDigest,
		StageStart:  uint32(r.view.cur),
		StageEnd:    uint32(r.view.curend),
		Change:      r.change,
	}, nil
}

// refArgs are the arguments naming a report's lease.
func refArgs(ref store.LeaseRef) []any {
	return []any{ref.TaskID, ref.WorkerID, strconv.FormatUint(ref.Epoch, 10)}
}

// policy is the retry policy fail() in scripts.go reads: "attempts block base cap", the
// backoffs in µs.
func (s *Store) policy() string {
	o := s.opts
	return fmt.Sprintf("%d %d %d %d", o.MaxAttempts, o.BlockAfterFailures, o.RetryBackoff.Microseconds(), o.MaxRetryBackoff.Microseconds())
}

// exemptPhases lists the phases the stuck check skips, for extendScript.
func exemptPhases() string {
	var b strings.Builder
	for _, p := range store.BuilderPhases {
		fmt.Fprintf(&b, "%d,", int32(p))
	}
	return b.String()
}

// ExtendLeases implements store.Store.
func (s *Store) ExtendLeases(ctx context.Context, workerID string, held []*pb.HeldLease) (store.Heartbeat, error) {
	var hb store.Heartbeat
	if len(held) == 0 {
		return hb, nil
	}
	now := s.opts.Clock.Now()
	expire := now.Add(s.opts.LeaseDuration)
	args := []any{workerID, micros(expire), micros(now.Add(-s.opts.StuckTimeout)), s.opts.StuckMessage(), s.policy(), exemptPhases()}
	for _, h := range held {
		args = append(args, h.GetTaskId(), strconv.FormatUint(h.GetEpoch(), 10), strconv.FormatUint(h.GetProgress(), 10))
	}
	v, err := s.run(ctx, extendScript, args...)
	if err != nil {
		return hb, err
	}
	answers, _ := v.([]any)
	if len(answers) != len(held) {
		return hb, errs.E(errs.Internal, "extend answered %d times for %d leases", len(answers), len(held))
	}
	for i, h := range held {
		switch a := answers[i].(type) {
		case int64:
			if a == 1 {
				hb.Extended = append(hb.Extended, &pb.Lease{TaskId: h.GetTaskId(), Epoch: h.GetEpoch(), ExpireTime: timestamppb.New(expire)})
				continue
			}
		default: // stuck: revoked and failed
			r, err := s.decodeReply(ctx, a)
			if err != nil {
				return hb, err
			}
			hb.Changes = append(hb.Changes, r.change)
		}
		hb.Revoked = append(hb.Revoked, &pb.HeldLease{TaskId: h.GetTaskId(), Epoch: h.GetEpoch()})
	}
	return hb, nil
}

// ExpireBatch is how many expired leases one expireScript looks at: a sweep after many
// workers died runs several short scripts rather than one long one. PromoteBatch is how
// many tasks whose backoff has ended a lease moves back to their queues (scripts.go,
// promote); the others go at the next leases.
const (
	ExpireBatch  = 256
	PromoteBatch = 64
)

// ExpireLeases implements store.Store.
func (s *Store) ExpireLeases(ctx context.Context) ([]store.Change, error) {
	var all []store.Change
	for {
		v, err := s.run(ctx, expireScript, s.opts.MaxExpiries, store.ExpiredMessage, ExpireBatch)
		if err != nil {
			return all, err
		}
		l, _ := v.([]any)
		if len(l) == 0 {
			return all, errs.E(errs.Internal, "unexpected expire answer %v", v)
		}
		cs, err := s.decodeChanges(ctx, l[1:])
		all = append(all, cs...)
		if err != nil || l[0] != int64(ExpireBatch) {
			return all, err
		}
	}
}

// CompleteTask implements store.Store.
func (s *Store) CompleteTask(ctx context.Context, ref store.LeaseRef, outputs []*pb.Artifact) (store.Change, error) {
	outs, err := encodeArtifacts(outputs)
	if err != nil {
		return store.Change{}, errs.Wrap(errs.Internal, err, "encode outputs")
	}
	r, err := s.change(ctx, completeScript, append(refArgs(ref), outs)...)
	return r.change, err
}

// CompleteRound implements store.Store.
func (s *Store) CompleteRound(ctx context.Context, ref store.LeaseRef, end store.RoundEnd) (store.Change, error) {
	if end.Report == nil {
		return store.Change{}, errs.E(errs.Internal, "CompleteRound needs the round's report")
	}
	// The script checks that the next round starts after the composite's stage.
	if err := store.CheckPlan(end.Next); err != nil {
		return store.Change{}, errs.Wrap(errs.Internal, err, "next round")
	}
	outs, err := encodeArtifacts(end.Outputs)
	if err != nil {
		return store.Change{}, errs.Wrap(errs.Internal, err, "encode outputs")
	}
	final, err := encodeArtifacts(end.Final)
	if err != nil {
		return store.Change{}, errs.Wrap(errs.Internal, err, "encode final outputs")
	}
	report, err := proto.Marshal(end.Report)
	if err != nil {
		return store.Change{}, errs.Wrap(errs.Internal, err, "encode round report")
	}
	// The next round's tasks go after the composite, the job's last task ("{job}.{index}").
	k := strings.LastIndexByte(ref.TaskID, '.')
	index, perr := strconv.ParseUint(ref.TaskID[k+1:], 10, 32)
	if k < 0 || perr != nil {
		return store.Change{}, &errs.Error{Kind: errs.NotFound, Field: "task_id", Message: fmt.Sprintf("no task %q", ref.TaskID)}
	}
	n := len(end.Next)
	var (
		stages, counts string
		round          uint32
	)
	if n > 0 {
		owner := ref.TaskID + "@" + strconv.FormatUint(ref.Epoch, 10)
		staged, err := s.stage(ctx, ref.TaskID[:k], owner, &ref, uint32(index)+1, end.Next)
		if err != nil {
			return store.Change{}, err
		}
		if !staged {
			n = 0 // a repeated report, which the script answers
		}
		stages, counts, round = summary(end.Next, uint32(index)+1)
	}
	metrics, err := proto.MarshalOptions{Deterministic: true}.Marshal(store.Metrics(end.Report))
	if err != nil {
		return store.Change{}, errs.Wrap(errs.Internal, err, "encode round metrics")
	}
	args := append(refArgs(ref), outs, report, final, n, "", "", "", "", metrics)
	if n > 0 {
		args[7], args[8], args[9], args[10] = strconv.FormatUint(store.Stage(end.Next[0]), 10), stages, counts, round
	}
	r, err := s.change(ctx, completeRoundScript, args...)
	return r.change, err
}

// FailTask implements store.Store.
func (s *Store) FailTask(ctx context.Context, ref store.LeaseRef, f store.Failure) (store.Change, error) {
	jobError := ""
	if f.Permanent() {
		jobError = store.PermanentFailure(ref.TaskID, f.Message)
	}
	var log []byte
	if f.Log != nil {
		var err error
		if log, err = proto.Marshal(f.Log); err != nil {
			return store.Change{}, errs.Wrap(errs.Internal, err, "encode task log")
		}
	}
	r, err := s.change(ctx, failScript, append(refArgs(ref), f.Message, s.policy(), int32(f.Kind), jobError, log)...)
	return r.change, err
}

// FailBlockedJob implements store.Store.
func (s *Store) FailBlockedJob(ctx context.Context, jobID string, workers []string) (store.Change, error) {
	args := []any{jobID, store.BlockedJobFailure(len(workers), "")}
	for _, w := range workers {
		args = append(args, w)
	}
	r, err := s.change(ctx, failBlockedScript, args...)
	return r.change, err
}

// ReleaseTask implements store.Store.
func (s *Store) ReleaseTask(ctx context.Context, ref store.LeaseRef) (store.Change, error) {
	r, err := s.change(ctx, releaseScript, refArgs(ref)...)
	return r.change, err
}

// ReleaseWorker implements store.Store.
func (s *Store) ReleaseWorker(ctx context.Context, workerID string) ([]store.Change, error) {
	return s.changes(ctx, releaseWorkerScript, workerID)
}

// CancelJob implements store.Store.
func (s *Store) CancelJob(ctx context.Context, jobID string) (store.Change, error) {
	r, err := s.change(ctx, cancelScript, jobID)
	return r.change, err
}

// ReopenJob implements store.Store: one reopenScript.
func (s *Store) ReopenJob(ctx context.Context, jobID, failedTask string) (store.Change, error) {
	r, err := s.change(ctx, reopenScript, jobID, failedTask)
	return r.change, err
}

// DeleteJob implements store.Store: one deleteScript; PurgeJobs deletes the records.
func (s *Store) DeleteJob(ctx context.Context, jobID string) (store.Change, error) {
	r, err := s.change(ctx, deleteScript, jobID)
	return r.change, err
}

// SetJobPriority implements store.Store.
func (s *Store) SetJobPriority(ctx context.Context, jobID string, priority int32) (store.Change, error) {
	if err := store.CheckPriority(priority); err != nil {
		return store.Change{}, err
	}
	r, err := s.change(ctx, priorityScript, jobID, priority)
	return r.change, err
}

// UnblockWorker implements store.Store.
func (s *Store) UnblockWorker(ctx context.Context, jobID, workerID string) (store.Change, error) {
	r, err := s.change(ctx, unblockScript, jobID, workerID)
	return r.change, err
}
