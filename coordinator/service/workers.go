package service

import (
	"context"
	"fmt"
	"time"

	"google.golang.org/grpc/metadata"
	"google.golang.org/protobuf/types/known/durationpb"

	"photonfarm/contract/rules"
	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

type workerServer struct {
	pb.UnimplementedWorkerServiceServer
	s *Service
}

var _ pb.WorkerServiceServer = (*workerServer)(nil)

// ListWorkers returns a page of the registered workers, oldest first: LOST if not heard
// from for longer than a lease lasts, else BUSY while holding a lease, else IDLE.
func (j *jobServer) ListWorkers(ctx context.Context, req *pb.ListWorkersRequest) (*pb.ListWorkersResponse, error) {
	s := j.s
	n, err := pageSize("page_size", req.GetPageSize(), DefaultWorkersPage, MaxWorkersPage)
	if err != nil {
		return nil, err
	}
	workers, next, err := s.workers.List(ctx, s.cfg.Clock.Now(), s.cfg.LeaseDuration, n, req.GetPageToken())
	if err != nil {
		return nil, err
	}
	return &pb.ListWorkersResponse{Workers: workers, NextPageToken: next}, nil
}

// ForgetSilentWorkers forgets the workers not heard from for ForgetAfterLeases lease
// durations. The coordinator calls it periodically.
func (s *Service) ForgetSilentWorkers(ctx context.Context) error {
	n, err := s.workers.ForgetSilent(ctx, s.cfg.Clock.Now(), ForgetAfterLeases*s.cfg.LeaseDuration)
	if n > 0 {
		s.log.Info("forgot silent workers", "workers", n, "silent_for", ForgetAfterLeases*s.cfg.LeaseDuration)
	}
	return err
}

func (ws *workerServer) RegisterWorker(ctx context.Context, req *pb.RegisterWorkerRequest) (*pb.RegisterWorkerResponse, error) {
	s := ws.s
	if len(req.GetHostname()) > 255 {
		return nil, errs.Field("hostname", "must be at most 255 bytes, got %d", len(req.GetHostname()))
	}
	if len(req.GetVersion()) > 255 {
		return nil, errs.Field("version", "must be at most 255 bytes, got %d", len(req.GetVersion()))
	}
	now := s.cfg.Clock.Now()
	secret, id := newWorkerSecret()
	w := store.Worker{ID: id, Hostname: req.GetHostname(), Cores: req.GetCores(), Version: req.GetVersion(), Registered: now, LastSeen: now}
	if err := s.workers.Add(ctx, w, s.cfg.LeaseDuration); err != nil {
		return nil, err
	}
	s.log.Info("worker registered", "worker", id, "hostname", req.GetHostname(), "cores", req.GetCores(), "version", req.GetVersion())
	return &pb.RegisterWorkerResponse{
		WorkerId:          id,
		WorkerSecret:      secret,
		HeartbeatInterval: durationpb.New(s.cfg.HeartbeatInterval),
		LeaseDuration:     durationpb.New(s.cfg.LeaseDuration),
	}, nil
}

// checkWorker checks the worker_id of a call about a worker and that the call carries
// that registration's secret (worker.proto): a worker token alone may not act for
// another worker. The secret is not named in the answer.
func checkWorker(ctx context.Context, id string) error {
	if err := checkID("worker_id", id); err != nil {
		return err
	}
	md, _ := metadata.FromIncomingContext(ctx)
	secrets := md.Get(rules.WorkerSecretMetadata)
	switch {
	case len(secrets) == 0:
		return &errs.Error{Kind: errs.PermissionDenied, Field: "worker_id",
			Message: fmt.Sprintf("a call about worker %s must carry the metadata %q that its RegisterWorker answered", id, rules.WorkerSecretMetadata)}
	case len(secrets) > 1 || !secretFits(id, secrets[0]):
		return &errs.Error{Kind: errs.PermissionDenied, Field: "worker_id",
			Message: fmt.Sprintf("the %q metadata is not worker %s's: a worker acts only for its own registration", rules.WorkerSecretMetadata, id)}
	}
	return nil
}

func (ws *workerServer) Heartbeat(ctx context.Context, req *pb.HeartbeatRequest) (*pb.HeartbeatResponse, error) {
	s := ws.s
	if err := checkWorker(ctx, req.GetWorkerId()); err != nil {
		return nil, err
	}
	for i, l := range req.GetLeases() {
		if err := checkID(fmt.Sprintf("leases[%d].task_id", i), l.GetTaskId()); err != nil {
			return nil, err
		}
		if l.GetEpoch() == 0 {
			return nil, errs.Field(fmt.Sprintf("leases[%d].epoch", i), "must be > 0 (the epoch the lease was granted under)")
		}
	}
	if err := s.workers.Touch(ctx, req.GetWorkerId(), s.cfg.Clock.Now()); err != nil {
		return nil, err
	}
	ext, rev, err := s.Extend(ctx, req.GetWorkerId(), req.GetLeases())
	if err != nil {
		return nil, err
	}
	return &pb.HeartbeatResponse{Leases: ext, Revoked: rev}, nil
}

// LeaseTask long-polls for a task of the phases workers take (never BUILD): it tries to
// lease, and if nothing is queued waits until tasks are queued, the wait times out, the
// caller gives up, or the coordinator shuts down.
func (ws *workerServer) LeaseTask(ctx context.Context, req *pb.LeaseTaskRequest) (*pb.LeaseTaskResponse, error) {
	s := ws.s
	if err := checkWorker(ctx, req.GetWorkerId()); err != nil {
		return nil, err
	}
	var wait time.Duration
	if d := req.GetWaitTimeout(); d != nil {
		if err := d.CheckValid(); err != nil {
			return nil, errs.Field("wait_timeout", "%v", err)
		}
		if wait = d.AsDuration(); wait < 0 {
			return nil, errs.Field("wait_timeout", "must be >= 0, got %v", wait)
		}
		wait = min(wait, MaxLeaseWait)
	}
	if err := s.workers.Touch(ctx, req.GetWorkerId(), s.cfg.Clock.Now()); err != nil {
		return nil, err
	}
	return s.Lease(ctx, req.GetWorkerId(), store.WorkerPhases, wait)
}

// leaseReport is a report under a lease: CompleteTask, FailTask and ReleaseTask.
type leaseReport interface {
	GetWorkerId() string
	GetTaskId() string
	GetEpoch() uint64
}

// onLease validates the lease fields of req and the worker's secret in ctx, and applies
// the report to the lease they name; the response, empty, is Resp's.
func onLease[Resp any](ctx context.Context, req leaseReport, apply func(store.LeaseRef) error) (*Resp, error) {
	if err := checkWorker(ctx, req.GetWorkerId()); err != nil {
		return nil, err
	}
	if err := checkID("task_id", req.GetTaskId()); err != nil {
		return nil, err
	}
	if req.GetEpoch() == 0 {
		return nil, errs.Field("epoch", "must be > 0 (the epoch the lease was granted under)")
	}
	if err := apply(store.LeaseRef{WorkerID: req.GetWorkerId(), TaskID: req.GetTaskId(), Epoch: req.GetEpoch()}); err != nil {
		return nil, err
	}
	return new(Resp), nil
}

func (ws *workerServer) CompleteTask(ctx context.Context, req *pb.CompleteTaskRequest) (*pb.CompleteTaskResponse, error) {
	return onLease[pb.CompleteTaskResponse](ctx, req, func(ref store.LeaseRef) error {
		if err := ws.s.CompleteWithMetrics(ctx, ref, req.GetOutputs(), req.GetMetrics()); err != nil {
			return err
		}
		ws.s.cfg.Metrics.TileSamplesRendered(req.GetSamples())
		return nil
	})
}

func (ws *workerServer) FailTask(ctx context.Context, req *pb.FailTaskRequest) (*pb.FailTaskResponse, error) {
	return onLease[pb.FailTaskResponse](ctx, req, func(ref store.LeaseRef) error {
		return ws.s.Fail(ctx, ref, store.Failure{Message: req.GetError(), Kind: req.GetKind(), Log: req.GetLog()})
	})
}

func (ws *workerServer) ReleaseTask(ctx context.Context, req *pb.ReleaseTaskRequest) (*pb.ReleaseTaskResponse, error) {
	return onLease[pb.ReleaseTaskResponse](ctx, req, func(ref store.LeaseRef) error { return ws.s.Release(ctx, ref) })
}

// UnregisterWorker forgets the worker and releases its leases. It is idempotent.
func (ws *workerServer) UnregisterWorker(ctx context.Context, req *pb.UnregisterWorkerRequest) (*pb.UnregisterWorkerResponse, error) {
	s := ws.s
	if err := checkWorker(ctx, req.GetWorkerId()); err != nil {
		return nil, err
	}
	if err := s.workers.Remove(ctx, req.GetWorkerId()); err != nil {
		return nil, err
	}
	changes, err := s.cfg.Store.ReleaseWorker(ctx, req.GetWorkerId())
	for _, c := range changes {
		s.publish(c)
	}
	if err != nil {
		return nil, err
	}
	s.log.Info("worker unregistered", "worker", req.GetWorkerId(), "released", len(changes))
	return &pb.UnregisterWorkerResponse{}, nil
}
