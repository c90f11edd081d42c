package service

import (
	"context"
	"crypto/rand"
	"encoding/hex"
	"fmt"
	"slices"
	"strings"
	"sync"
	"time"

	"google.golang.org/protobuf/types/known/durationpb"
	"google.golang.org/protobuf/types/known/timestamppb"

	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

type workerServer struct {
	pb.UnimplementedWorkerServiceServer
	s *Service
}

var _ pb.WorkerServiceServer = (*workerServer)(nil)

// registry is the in-memory list of registered workers and what each is doing, for
// ListWorkers. Leases themselves live in the store; the registry only mirrors what this
// coordinator saw (grants, reports, revocations, expiries), so another replica's view of
// a worker may differ.
type registry struct {
	mu sync.Mutex
	m  map[string]*worker
}

type worker struct {
	hostname string
	cores    uint32
	version  string
	// registered is when it registered; lastSeen when it last heartbeat or polled.
	registered, lastSeen time.Time
	// current is the task it holds a lease on ("" if none): the latest lease granted.
	current string
	// done and failed count the tasks it completed and failed (lost leases included).
	done, failed uint64
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

// leased records that id was granted a lease on taskID. Unknown ids (the coordinator's
// builder) are ignored, as in the methods below.
func (r *registry) leased(id, taskID string) {
	r.mu.Lock()
	defer r.mu.Unlock()
	if w := r.m[id]; w != nil {
		w.current = taskID
	}
}

// ended records that id's attempt at taskID ended, successfully (ok) or not.
func (r *registry) ended(id, taskID string, ok bool) {
	r.mu.Lock()
	defer r.mu.Unlock()
	w := r.m[id]
	if w == nil {
		return
	}
	if ok {
		w.done++
	} else {
		w.failed++
	}
	if w.current == taskID {
		w.current = ""
	}
}

// dropped records that id no longer holds taskID (released, revoked), counting nothing.
func (r *registry) dropped(id, taskID string) {
	r.mu.Lock()
	defer r.mu.Unlock()
	if w := r.m[id]; w != nil && w.current == taskID {
		w.current = ""
	}
}

// expired records that the lease on taskID expired: its holder (the store no longer names
// it) failed the task.
func (r *registry) expired(taskID string) {
	r.mu.Lock()
	defer r.mu.Unlock()
	for _, w := range r.m {
		if w.current == taskID {
			w.current = ""
			w.failed++
		}
	}
}

// list returns every worker by registration time, oldest first; a worker not heard from
// for longer than lost is LOST.
func (r *registry) list(now time.Time, lost time.Duration) []*pb.WorkerInfo {
	r.mu.Lock()
	defer r.mu.Unlock()
	out := make([]*pb.WorkerInfo, 0, len(r.m))
	for id, w := range r.m {
		state := pb.WorkerState_WORKER_STATE_IDLE
		switch {
		case now.Sub(w.lastSeen) > lost:
			state = pb.WorkerState_WORKER_STATE_LOST
		case w.current != "":
			state = pb.WorkerState_WORKER_STATE_BUSY
		}
		out = append(out, &pb.WorkerInfo{
			Id:            id,
			Hostname:      w.hostname,
			Cores:         w.cores,
			Version:       w.version,
			State:         state,
			CurrentTaskId: w.current,
			TasksDone:     w.done,
			TasksFailed:   w.failed,
			RegisterTime:  timestamppb.New(w.registered),
			LastHeartbeat: timestamppb.New(w.lastSeen),
		})
	}
	slices.SortFunc(out, func(a, b *pb.WorkerInfo) int {
		if c := a.RegisterTime.AsTime().Compare(b.RegisterTime.AsTime()); c != 0 {
			return c
		}
		return strings.Compare(a.Id, b.Id)
	})
	return out
}

// live returns the ids of the workers heard from within lost: registered and not LOST.
func (r *registry) live(now time.Time, lost time.Duration) []string {
	r.mu.Lock()
	defer r.mu.Unlock()
	var ids []string
	for id, w := range r.m {
		if now.Sub(w.lastSeen) <= lost {
			ids = append(ids, id)
		}
	}
	slices.Sort(ids)
	return ids
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

// ListWorkers returns the registered workers, oldest first: LOST if not heard from for
// longer than a lease lasts, else BUSY while holding a lease, else IDLE.
func (j *jobServer) ListWorkers(ctx context.Context, req *pb.ListWorkersRequest) (*pb.ListWorkersResponse, error) {
	s := j.s
	return &pb.ListWorkersResponse{Workers: s.workers.list(s.cfg.Clock.Now(), s.cfg.LeaseDuration)}, nil
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
	id := s.workers.add(&worker{hostname: req.GetHostname(), cores: req.GetCores(), version: req.GetVersion(), registered: now, lastSeen: now})
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

// leaseReport is a report under a lease: CompleteTask, FailTask and ReleaseTask.
type leaseReport interface {
	GetWorkerId() string
	GetTaskId() string
	GetEpoch() uint64
}

// onLease validates the lease fields of req and applies the report to the lease they
// name; the response, empty, is Resp's.
func onLease[Resp any](req leaseReport, apply func(store.LeaseRef) error) (*Resp, error) {
	if err := checkID("worker_id", req.GetWorkerId()); err != nil {
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
	return onLease[pb.CompleteTaskResponse](req, func(ref store.LeaseRef) error {
		return ws.s.CompleteWithMetrics(ctx, ref, req.GetOutputs(), req.GetMetrics())
	})
}

func (ws *workerServer) FailTask(ctx context.Context, req *pb.FailTaskRequest) (*pb.FailTaskResponse, error) {
	return onLease[pb.FailTaskResponse](req, func(ref store.LeaseRef) error {
		return ws.s.Fail(ctx, ref, store.Failure{Message: req.GetError(), Kind: req.GetKind()})
	})
}

func (ws *workerServer) ReleaseTask(ctx context.Context, req *pb.ReleaseTaskRequest) (*pb.ReleaseTaskResponse, error) {
	return onLease[pb.ReleaseTaskResponse](req, func(ref store.LeaseRef) error { return ws.s.Release(ctx, ref) })
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
