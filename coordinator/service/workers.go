package service

import (
	"context"
	"crypto/rand"
	"encoding/hex"
	"fmt"
	"sync"
	"time"

	"google.golang.org/protobuf/types/known/durationpb"

	"photonfarm/coordinator/blobstore"
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

func (r *registry) remove(id string) {
	r.mu.Lock()
	defer r.mu.Unlock()
	delete(r.m, id)
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
	if err := required("worker_id", req.GetWorkerId()); err != nil {
		return nil, err
	}
	for i, l := range req.GetLeases() {
		if l.GetTaskId() == "" {
			return nil, errs.Field(fmt.Sprintf("leases[%d].task_id", i), "must be non-empty")
		}
	}
	if err := s.workers.touch(req.GetWorkerId(), s.cfg.Clock.Now()); err != nil {
		return nil, err
	}
	ext, rev, err := s.cfg.Store.ExtendLeases(ctx, req.GetWorkerId(), req.GetLeases())
	if err != nil {
		return nil, err
	}
	return &pb.HeartbeatResponse{Leases: ext, Revoked: rev}, nil
}

// LeaseTask long-polls: it tries to lease, and if nothing is queued waits until tasks are
// queued, the wait times out, the caller gives up, or the coordinator shuts down.
func (ws *workerServer) LeaseTask(ctx context.Context, req *pb.LeaseTaskRequest) (*pb.LeaseTaskResponse, error) {
	s := ws.s
	if err := required("worker_id", req.GetWorkerId()); err != nil {
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
	var timeout <-chan time.Time
	if wait > 0 {
		t := time.NewTimer(wait)
		defer t.Stop()
		timeout = t.C
	}
	for {
		wake := s.queued.wait()
		l, err := s.cfg.Store.LeaseTask(ctx, req.GetWorkerId())
		if err != nil {
			return nil, err
		}
		if l != nil {
			return ws.granted(ctx, req.GetWorkerId(), l)
		}
		if wait == 0 {
			return &pb.LeaseTaskResponse{}, nil
		}
		select {
		case <-wake:
		case <-timeout:
			return &pb.LeaseTaskResponse{}, nil
		case <-s.done:
			return &pb.LeaseTaskResponse{}, nil
		case <-ctx.Done():
			return nil, ctx.Err()
		}
	}
}

// granted completes a lease: the composite task learns its tiles.
func (ws *workerServer) granted(ctx context.Context, workerID string, l *store.Leased) (*pb.LeaseTaskResponse, error) {
	s := ws.s
	s.publish(l.Change)
	if comp := l.Task.GetComposite(); comp != nil {
		tiles, err := ws.tiles(ctx, l.Task.GetJobId())
		if err != nil {
			// Hand the lease back rather than let it expire.
			if c, rerr := s.cfg.Store.ReleaseTask(ctx, store.LeaseRef{WorkerID: workerID, TaskID: l.Lease.GetTaskId(), Epoch: l.Lease.GetEpoch()}); rerr == nil {
				s.publish(c)
			}
			return nil, err
		}
		comp.Tiles = tiles
	}
	s.log.Debug("task leased", "task", l.Task.GetId(), "worker", workerID, "epoch", l.Lease.GetEpoch(), "attempt", l.Task.GetAttempts())
	return &pb.LeaseTaskResponse{Lease: l.Lease, Task: l.Task, SceneDigest: l.SceneDigest}, nil
}

// tiles lists the rectangles and tile artifacts of a job's render phase.
func (ws *workerServer) tiles(ctx context.Context, jobID string) ([]*pb.TileInput, error) {
	var tiles []*pb.TileInput
	token := ""
	for {
		tasks, next, err := ws.s.cfg.Store.ListTasks(ctx, jobID, MaxTasksPage, token)
		if err != nil {
			return nil, err
		}
		for _, t := range tasks {
			rt := t.GetRenderTile()
			if rt == nil {
				continue
			}
			if t.GetState() != pb.TaskState_TASK_STATE_SUCCEEDED || len(t.GetOutputs()) == 0 {
				return nil, errs.E(errs.Internal, "composite leased before tile task %s produced its tile", t.GetId())
			}
			tile := t.GetOutputs()[0]
			for _, o := range t.GetOutputs() {
				if o.GetName() == "tile.exr" {
					tile = o
					break
				}
			}
			tiles = append(tiles, &pb.TileInput{Rect: rt.GetRect(), Tile: tile})
		}
		if next == "" {
			return tiles, nil
		}
		token = next
	}
}

// leaseRef validates the lease fields shared by CompleteTask, FailTask and ReleaseTask.
func leaseRef(workerID, taskID string, epoch uint64) (store.LeaseRef, error) {
	if err := required("worker_id", workerID); err != nil {
		return store.LeaseRef{}, err
	}
	if err := required("task_id", taskID); err != nil {
		return store.LeaseRef{}, err
	}
	if epoch == 0 {
		return store.LeaseRef{}, errs.Field("epoch", "must be > 0 (the epoch the lease was granted under)")
	}
	return store.LeaseRef{WorkerID: workerID, TaskID: taskID, Epoch: epoch}, nil
}

func (ws *workerServer) CompleteTask(ctx context.Context, req *pb.CompleteTaskRequest) (*pb.CompleteTaskResponse, error) {
	s := ws.s
	ref, err := leaseRef(req.GetWorkerId(), req.GetTaskId(), req.GetEpoch())
	if err != nil {
		return nil, err
	}
	// Outputs must name blobs that were uploaded, with their true sizes.
	for i, a := range req.GetOutputs() {
		p := fmt.Sprintf("outputs[%d]", i)
		if a.GetName() == "" || len(a.GetName()) > 255 {
			return nil, errs.Field(p+".name", "must be 1 to 255 bytes, got %d", len(a.GetName()))
		}
		if !blobstore.ValidDigest(a.GetDigest()) {
			return nil, errs.Field(p+".digest", "must be \"sha256:\" followed by 64 lowercase hex digits, got %q", a.GetDigest())
		}
		info, err := s.cfg.Blobs.Stat(ctx, a.GetDigest())
		if errs.Is(err, errs.NotFound) {
			return nil, errs.Field(p+".digest", "no blob %s; upload it before completing the task", a.GetDigest())
		}
		if err != nil {
			return nil, err
		}
		if info.Size != a.GetSizeBytes() {
			return nil, errs.Field(p+".size_bytes", "blob %s has %d bytes, not %d", a.GetDigest(), info.Size, a.GetSizeBytes())
		}
	}
	c, err := s.cfg.Store.CompleteTask(ctx, ref, req.GetOutputs())
	if err != nil {
		return nil, err
	}
	if c.Task != nil {
		s.log.Debug("task completed", "task", ref.TaskID, "worker", ref.WorkerID, "epoch", ref.Epoch)
	}
	s.publish(c)
	return &pb.CompleteTaskResponse{}, nil
}

func (ws *workerServer) FailTask(ctx context.Context, req *pb.FailTaskRequest) (*pb.FailTaskResponse, error) {
	s := ws.s
	ref, err := leaseRef(req.GetWorkerId(), req.GetTaskId(), req.GetEpoch())
	if err != nil {
		return nil, err
	}
	msg := req.GetError()
	if msg == "" {
		return nil, errs.Field("error", "must say why the task failed")
	}
	if len(msg) > MaxErrorMessage {
		msg = msg[:MaxErrorMessage] + "…"
	}
	c, err := s.cfg.Store.FailTask(ctx, ref, msg)
	if err != nil {
		return nil, err
	}
	s.log.Warn("task failed", "task", ref.TaskID, "worker", ref.WorkerID, "epoch", ref.Epoch, "error", msg)
	s.publish(c)
	return &pb.FailTaskResponse{}, nil
}

func (ws *workerServer) ReleaseTask(ctx context.Context, req *pb.ReleaseTaskRequest) (*pb.ReleaseTaskResponse, error) {
	ref, err := leaseRef(req.GetWorkerId(), req.GetTaskId(), req.GetEpoch())
	if err != nil {
		return nil, err
	}
	c, err := ws.s.cfg.Store.ReleaseTask(ctx, ref)
	if err != nil {
		return nil, err
	}
	ws.s.publish(c)
	return &pb.ReleaseTaskResponse{}, nil
}

// UnregisterWorker forgets the worker and releases its leases. It is idempotent.
func (ws *workerServer) UnregisterWorker(ctx context.Context, req *pb.UnregisterWorkerRequest) (*pb.UnregisterWorkerResponse, error) {
	s := ws.s
	if err := required("worker_id", req.GetWorkerId()); err != nil {
		return nil, err
	}
	s.workers.remove(req.GetWorkerId())
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
