package service

import (
	"context"
	"crypto/rand"
	"encoding/hex"
	"fmt"
	"sync"
	"time"

	"google.golang.org/protobuf/types/known/durationpb"

	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

type workerServer struct {
	pb.UnimplementedWorkerServiceServer
	s *Service
}

var _ pb.WorkerServiceServer = (*workerServer)(nil)

// registry is the in-memory list of registered workers.
type registry struct {
	mu sync.Mutex
	m  map[string]*worker
}

type worker struct {
	hostname string
	cores    uint32
	version  string
	lastSeen time.Time
}

func (r *registry) add(w *worker) string {
	r.mu.Lock()
	defer r.mu.Unlock()
	for {
		var b [6]byte
		_, _ = rand.Read(b[:])
		id := "w-" + hex.EncodeToString(b[:])
		if r.m[id] == nil {
			r.m[id] = w
			return id
		}
	}
}

// touch records that id was heard from; it fails for an unknown worker.
func (r *registry) touch(id string, now time.Time) error {
	r.mu.Lock()
	defer r.mu.Unlock()
	w := r.m[id]
	if w == nil {
		return &errs.Error{Kind: errs.NotFound, Field: "worker_id", Message: fmt.Sprintf("unknown worker %q; register again", id)}
	}
	w.lastSeen = now
	return nil
}

// remove forgets a worker; NotFound if it was not registered.
func (r *registry) remove(id string) error {
	r.mu.Lock()
	defer r.mu.Unlock()
	if r.m[id] == nil {
		return &errs.Error{Kind: errs.NotFound, Field: "worker_id", Message: fmt.Sprintf("unknown worker %q", id)}
	}
	delete(r.m, id)
	return nil
}

func (ws *workerServer) RegisterWorker(ctx context.Context, req *pb.RegisterWorkerRequest) (*pb.RegisterWorkerResponse, error) {
	s := ws.s
	if len(req.GetHostname()) > 255 {
		return nil, errs.Field("hostname", "must be at most 255 bytes, got %d", len(req.GetHostname()))
	}
	if len(req.GetVersion()) > 255 {
		return nil, errs.Field("version", "must be at most 255 bytes, got %d", len(req.GetVersion()))
	}
	id := s.workers.add(&worker{hostname: req.GetHostname(), cores: req.GetCores(), version: req.GetVersion(), lastSeen: s.cfg.Clock.Now()})
	s.log.Info("worker registered", "worker", id, "hostname", req.GetHostname(), "cores", req.GetCores(), "version", req.GetVersion())
	return &pb.RegisterWorkerResponse{
		WorkerId:          id,
		HeartbeatInterval: durationpb.New(s.cfg.HeartbeatInterval),
		LeaseDuration:     durationpb.New(s.cfg.LeaseDuration),
	}, nil
}

func (ws *workerServer) Heartbeat(ctx context.Context, req *pb.HeartbeatRequest) (*pb.HeartbeatResponse, error) {
	s := ws.s
	if err := checkID("worker_id", req.GetWorkerId()); err != nil {
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
	if err := s.workers.touch(req.GetWorkerId(), s.cfg.Clock.Now()); err != nil {
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
	if err := checkID("worker_id", req.GetWorkerId()); err != nil {
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
	if err := s.workers.touch(req.GetWorkerId(), s.cfg.Clock.Now()); err != nil {
		return nil, err
	}
	return s.Lease(ctx, req.GetWorkerId(), store.WorkerPhases, wait)
}

// leaseRef validates the lease fields shared by CompleteTask, FailTask and ReleaseTask.
func leaseRef(workerID, taskID string, epoch uint64) (store.LeaseRef, error) {
	if err := checkID("worker_id", workerID); err != nil {
		return store.LeaseRef{}, err
	}
	if err := checkID("task_id", taskID); err != nil {
		return store.LeaseRef{}, err
	}
	if epoch == 0 {
		return store.LeaseRef{}, errs.Field("epoch", "must be > 0 (the epoch the lease was granted under)")
	}
	return store.LeaseRef{WorkerID: workerID, TaskID: taskID, Epoch: epoch}, nil
}

func (ws *workerServer) CompleteTask(ctx context.Context, req *pb.CompleteTaskRequest) (*pb.CompleteTaskResponse, error) {
	ref, err := leaseRef(req.GetWorkerId(), req.GetTaskId(), req.GetEpoch())
	if err != nil {
		return nil, err
	}
	if err := ws.s.CompleteWithMetrics(ctx, ref, req.GetOutputs(), req.GetMetrics()); err != nil {
		return nil, err
	}
	return &pb.CompleteTaskResponse{}, nil
}

func (ws *workerServer) FailTask(ctx context.Context, req *pb.FailTaskRequest) (*pb.FailTaskResponse, error) {
	ref, err := leaseRef(req.GetWorkerId(), req.GetTaskId(), req.GetEpoch())
	if err != nil {
		return nil, err
	}
	if err := ws.s.Fail(ctx, ref, req.GetError()); err != nil {
		return nil, err
	}
	return &pb.FailTaskResponse{}, nil
}

func (ws *workerServer) ReleaseTask(ctx context.Context, req *pb.ReleaseTaskRequest) (*pb.ReleaseTaskResponse, error) {
	ref, err := leaseRef(req.GetWorkerId(), req.GetTaskId(), req.GetEpoch())
	if err != nil {
		return nil, err
	}
	if err := ws.s.Release(ctx, ref); err != nil {
		return nil, err
	}
	return &pb.ReleaseTaskResponse{}, nil
}

// UnregisterWorker forgets the worker and releases its leases. It is idempotent.
func (ws *workerServer) UnregisterWorker(ctx context.Context, req *pb.UnregisterWorkerRequest) (*pb.UnregisterWorkerResponse, error) {
	s := ws.s
	if err := checkID("worker_id", req.GetWorkerId()); err != nil {
		return nil, err
	}
	if err := s.workers.remove(req.GetWorkerId()); err != nil {
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
