package redisstore

import (
	"context"
	"strconv"

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
	args := []any{workerID, micros(s.opts.Clock.Now().Add(s.opts.LeaseDuration))}
	for _, p := range phases {
		args = append(args, int32(p))
	}
	r, err := s.change(ctx, leaseScript, args...)
	if err != nil || r.none {
		return nil, err
	}
	return &store.Leased{
		Lease:       &pb.Lease{TaskId: r.change.Task.Id, Epoch: number(r.task["epoch"]), ExpireTime: timestamp(r.task["expire"])},
		Task:        r.change.Task,
		SceneDigest: r.change.Job.SceneDigest,
		Change:      r.change,
	}, nil
}

// refArgs are the arguments naming a report's lease.
func refArgs(ref store.LeaseRef) []any {
	return []any{ref.TaskID, ref.WorkerID, strconv.FormatUint(ref.Epoch, 10)}
}

// ExtendLeases implements store.Store.
func (s *Store) ExtendLeases(ctx context.Context, workerID string, held []*pb.HeldLease) ([]*pb.Lease, []*pb.HeldLease, error) {
	if len(held) == 0 {
		return nil, nil, nil
	}
	expire := s.opts.Clock.Now().Add(s.opts.LeaseDuration)
	args := []any{workerID, micros(expire)}
	for _, h := range held {
		args = append(args, h.GetTaskId(), strconv.FormatUint(h.GetEpoch(), 10))
	}
	v, err := s.run(ctx, extendScript, args...)
	if err != nil {
		return nil, nil, err
	}
	flags, _ := v.([]any)
	if len(flags) != len(held) {
		return nil, nil, errs.E(errs.Internal, "extend answered %d flags for %d leases", len(flags), len(held))
	}
	var extended []*pb.Lease
	var revoked []*pb.HeldLease
	for i, h := range held {
		if flags[i] == int64(1) {
			extended = append(extended, &pb.Lease{TaskId: h.GetTaskId(), Epoch: h.GetEpoch(), ExpireTime: timestamppb.New(expire)})
		} else {
			revoked = append(revoked, &pb.HeldLease{TaskId: h.GetTaskId(), Epoch: h.GetEpoch()})
		}
	}
	return extended, revoked, nil
}

// ExpireLeases implements store.Store.
func (s *Store) ExpireLeases(ctx context.Context) ([]store.Change, error) {
	return s.changes(ctx, expireScript)
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
	for i, n := range end.Next {
		if n.GetIndex() != uint32(i) || (i > 0 && store.Stage(n) < store.Stage(end.Next[i-1])) {
			return store.Change{}, errs.E(errs.Internal, "next round's task %d is out of order", i)
		}
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
	next, err := taskArgs(end.Next)
	if err != nil {
		return store.Change{}, err
	}
	args := append(refArgs(ref), outs, report, final)
	r, err := s.change(ctx, completeRoundScript, append(args, next...)...)
	return r.change, err
}

// FailTask implements store.Store.
func (s *Store) FailTask(ctx context.Context, ref store.LeaseRef, message string) (store.Change, error) {
	r, err := s.change(ctx, failScript, append(refArgs(ref), message, s.opts.MaxAttempts)...)
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
