// Package service implements the gRPC services of renderfarm.v1 (JobService,
// WorkerService, BlobService) over a store.Store, a blob store and an events broker.
//
// Handlers return the coordinator's internal errors (errs.Error, scene.FieldError); the
// interceptors installed by NewGRPCServer turn them into gRPC statuses in one place
// (status.go).
package service

import (
	"context"
	"io"
	"log/slog"
	"slices"
	"sync"
	"time"

	"google.golang.org/grpc"
	"google.golang.org/grpc/health"
	healthpb "google.golang.org/grpc/health/grpc_health_v1"
	"google.golang.org/grpc/keepalive"
	"google.golang.org/protobuf/types/known/timestamppb"

	"photonfarm/contract/rules"
	"photonfarm/coordinator/blobstore"
	"photonfarm/coordinator/clock"
	"photonfarm/coordinator/events"
	"photonfarm/coordinator/metrics"
	"photonfarm/coordinator/store"
	"photonfarm/coordinator/store/memstore"
	pb "photonfarm/proto/renderfarm/v1"
)

// Blobs is what the service needs of a blob store.
type Blobs interface {
	Stat(ctx context.Context, digest string) (blobstore.Info, error)
	// Touch is Stat that also marks the blob in use now (blobstore's collection protocol).
	Touch(ctx context.Context, digest string) (blobstore.Info, error)
	Open(ctx context.Context, digest string) (io.ReadCloser, blobstore.Info, error)
	OpenRange(ctx context.Context, digest string, offset, length int64) (io.ReadCloser, blobstore.Info, error)
	Verify(ctx context.Context, digest string) (blobstore.Info, error)
	Put(ctx context.Context, r io.Reader, size int64, digest string) (blobstore.Info, error)
	Create(ctx context.Context, size int64, digest string) (*blobstore.Writer, error)
}

var _ Blobs = (*blobstore.Store)(nil)

// Events is what the service needs of an event broker.
type Events interface {
	Publish(ev *pb.WatchJobResponse)
	Watch(jobID string) *events.Watcher
	Watchers(jobID string) int
}

var _ Events = (*events.Broker)(nil)

// MaxLeaseWait bounds LeaseTaskRequest.wait_timeout (docs/limits.md). The RPC layer's
// byte limits (messages, chunks, blobs, error messages) are the contract's: rules.RPC.
const MaxLeaseWait = 30 * time.Second

// Config wires a Service.
type Config struct {
	Store store.Store
	// Metrics counts what happens to tasks and jobs; nil counts nothing.
	Metrics *metrics.Metrics
	Blobs   Blobs
	Events  Events
	// Workers is the worker registry; nil keeps one in memory (memstore.NewWorkers). Replicas
	// share one (redisstore.Store.Workers) to list the same workers.
	Workers store.Workers
	Clock   clock.Clock
	Logger  *slog.Logger
	// LeaseDuration and HeartbeatInterval are told to workers when they register; the
	// store enforces the lease duration.
	LeaseDuration     time.Duration
	HeartbeatInterval time.Duration
}

// Service holds the state shared by the three gRPC services.
type Service struct {
	cfg       Config
	log       *slog.Logger
	queued    notifier
	retries   retries
	workers   store.Workers
	blocked   blockedJobs
	snapshots *cache[*pb.Artifact] // by job and round
	scenes    *cache[*pb.Scene]    // by digest
	// verifiedSnapshots holds the digests of snapshots verified whole.
	verifiedSnapshots *cache[struct{}]
	// checked remembers the blobs that passed as a kind of file (checkedKey).
	checked *cache[struct{}]
	done    chan struct{}
	once    sync.Once
}

// New returns a Service; Store, Blobs and Events are required.
func New(cfg Config) *Service {
	if cfg.Clock == nil {
		cfg.Clock = clock.Real{}
	}
	if cfg.Logger == nil {
		cfg.Logger = slog.New(slog.DiscardHandler)
	}
	if cfg.LeaseDuration <= 0 {
		cfg.LeaseDuration = store.DefaultLeaseDuration
	}
	if cfg.Workers == nil {
		cfg.Workers = memstore.NewWorkers()
	}
	if cfg.HeartbeatInterval <= 0 {
		cfg.HeartbeatInterval = cfg.LeaseDuration / 4
	}
	return &Service{
		cfg:               cfg,
		log:               cfg.Logger,
		queued:            newNotifier(),
		workers:           cfg.Workers,
		blocked:           blockedJobs{ids: make(map[string]bool)},
		snapshots:         newCache[*pb.Artifact](1024),
		scenes:            newCache[*pb.Scene](64),
		verifiedSnapshots: newCache[struct{}](1024),
		checked:           newCache[struct{}](4096),
		done:              make(chan struct{}),
	}
}

// Connection limits of NewGRPCServer's server (docs/limits.md).
const (
	// MaxStreamsPerConnection bounds the calls in flight on one connection (HTTP/2
	// SETTINGS_MAX_CONCURRENT_STREAMS); a client's further calls wait for one to end.
	// The dashboard multiplexes every browser over one connection: its event streams
	// (dashboard.DefaultMaxStreams) must fit with room for its other calls.
	MaxStreamsPerConnection = 256
	// HandshakeTimeout bounds a new connection's TLS handshake and HTTP/2 preface.
	HandshakeTimeout = 10 * time.Second
	// MaxConnectionIdle closes a connection without a call for this long (its client
	// reconnects at its next call), so that idle connections do not pile up.
	MaxConnectionIdle = 5 * time.Minute
	// MaxHeaderBytes bounds a call's headers (HTTP/2 SETTINGS_MAX_HEADER_LIST_SIZE),
	// which gRPC reads before the token check: a token is at most 4096 bytes, and the
	// farm's other metadata is small. (gRPC's default is 16 MiB.)
	MaxHeaderBytes = 16 << 10
)

// NewGRPCServer returns a gRPC server with the three services and gRPC's standard health
// service registered (Kubernetes' grpc probes and grpc_health_probe call it; it needs no
// token; NOT_SERVING while the store or the blob store does not answer: health.go), the error mapping interceptors installed and message and connection limits set;
// opts are appended.
func (s *Service) NewGRPCServer(opts ...grpc.ServerOption) *grpc.Server {
	base := []grpc.ServerOption{
		grpc.MaxRecvMsgSize(int(rules.RPC.GetMaxMessageBytes())),
		grpc.MaxSendMsgSize(int(rules.RPC.GetMaxMessageBytes())),
		grpc.MaxConcurrentStreams(MaxStreamsPerConnection),
		grpc.MaxHeaderListSize(MaxHeaderBytes),
		grpc.ConnectionTimeout(HandshakeTimeout),
		grpc.KeepaliveParams(keepalive.ServerParameters{MaxConnectionIdle: MaxConnectionIdle}),
		grpc.ChainUnaryInterceptor(s.unaryErrors),
		grpc.ChainStreamInterceptor(s.streamErrors),
	}
	srv := grpc.NewServer(append(base, opts...)...)
	pb.RegisterJobServiceServer(srv, &jobServer{s: s})
	pb.RegisterWorkerServiceServer(srv, &workerServer{s: s})
	pb.RegisterBlobServiceServer(srv, &blobServer{s: s})
	h := health.NewServer()
	healthpb.RegisterHealthServer(srv, h)
	go s.watchHealth(h)
	return srv
}

// Shutdown ends long polls (LeaseTask returns nothing) and watches (WatchJob returns
// UNAVAILABLE) so that a graceful stop does not wait for them.
func (s *Service) Shutdown() { s.once.Do(func() { close(s.done) }) }

// ExpireLeases requeues tasks whose leases have expired and publishes the changes. The
// coordinator calls it periodically.
func (s *Service) ExpireLeases(ctx context.Context) error {
	changes, err := s.cfg.Store.ExpireLeases(ctx)
	for _, c := range changes {
		id := c.Task.GetId()
		s.mirror(ctx, "an expired lease", func(ctx context.Context) error { return s.workers.Expired(ctx, id) })
		s.cfg.Metrics.LeaseExpired()
		s.log.Info("lease expired", "task", c.Task.GetId(), "job", c.Job.GetId(), "attempts", c.Task.GetAttempts(), "job_state", c.Job.GetState().String())
		s.publish(c)
	}
	return err
}

// mirrorTimeout bounds one write to the worker registry.
const mirrorTimeout = 5 * time.Second

// mirror records in the worker registry what a worker did, once the store has committed
// it: with the caller's context values but not its cancellation (a worker that stopped
// waiting for the answer still did what the store recorded, and the registry must say so),
// within mirrorTimeout. A failure is logged: the registry only mirrors the store's leases
// for ListWorkers, so the call it belongs to goes on.
func (s *Service) mirror(ctx context.Context, what string, record func(context.Context) error) {
	ctx, cancel := context.WithTimeout(context.WithoutCancel(ctx), mirrorTimeout)
	defer cancel()
	if err := record(ctx); err != nil {
		s.log.Warn("worker registry: cannot record "+what, "err", err)
	}
}

// dropped records that ref's worker no longer holds its task, whatever the store said of
// the report (a report under a lease lost to a cancel is refused, and the worker has
// stopped working on the task all the same).
func (s *Service) dropped(ctx context.Context, ref store.LeaseRef) {
	s.mirror(ctx, "a report", func(ctx context.Context) error { return s.workers.Dropped(ctx, ref.WorkerID, ref.TaskID) })
}

// FollowReplicas hears of the changes other coordinators on the same store make
// (store.Feed) until ctx ends, and handles each as one of its own: events for this
// coordinator's watchers of the job, waiting workers woken when tasks were queued, jobs
// that block workers tracked (FailBlockedJobs). It reads the job and the task only when
// one of those needs them, so that followers cost the store little for the changes
// nobody here watches.
func (s *Service) FollowReplicas(ctx context.Context, feed store.Feed) error {
	return feed.Follow(ctx, func(r store.Remote) {
		if s.cfg.Events.Watchers(r.JobID) == 0 && r.TaskID != "" && !r.JobStateChanged && !r.Blocks {
			if r.Queued {
				s.queued.broadcast()
			}
			return
		}
		c, err := r.Load(ctx)
		if err != nil {
			if ctx.Err() == nil {
				s.log.Warn("reading another coordinator's change", "job", r.JobID, "task", r.TaskID, "err", err)
			}
			c = store.Change{Queued: r.Queued}
		}
		s.publish(c)
	})
}

// publish turns a store change into events and wakes waiting workers.
func (s *Service) publish(c store.Change) {
	if c.Job == nil {
		if c.Queued {
			s.queued.broadcast()
		}
		return
	}
	s.blocked.track(c.Job)
	now := timestamppb.New(s.cfg.Clock.Now())
	if c.Task != nil {
		s.cfg.Events.Publish(&pb.WatchJobResponse{Kind: pb.JobEventKind_JOB_EVENT_KIND_TASK_UPDATED, Time: now, Job: c.Job, Task: c.Task})
	}
	if c.JobStateChanged {
		s.cfg.Events.Publish(&pb.WatchJobResponse{Kind: pb.JobEventKind_JOB_EVENT_KIND_STATE_CHANGED, Time: now, Job: c.Job})
		s.log.Info("job state changed", "job", c.Job.GetId(), "state", c.Job.GetState().String(), "error", c.Job.GetError())
	}
	if c.Task == nil && !c.JobStateChanged {
		s.cfg.Events.Publish(&pb.WatchJobResponse{Kind: pb.JobEventKind_JOB_EVENT_KIND_JOB_UPDATED, Time: now, Job: c.Job})
	}
	if rt := c.Task.GetRetryTime(); rt != nil {
		// Waiting workers set their timers anew (Lease) and so wake when it may be leased.
		s.retries.add(rt.AsTime())
		s.queued.broadcast()
	} else if c.Queued {
		s.queued.broadcast()
	}
}

// retries remembers when tasks in backoff become leasable, so that a long poll also
// wakes then (putting a task back with a backoff makes nothing leasable now:
// store.Change.Queued). Only this coordinator's failures are known here; workers polling
// another replica find the task at their next poll.
type retries struct {
	mu sync.Mutex
	at []time.Time
}

func (r *retries) add(t time.Time) {
	r.mu.Lock()
	defer r.mu.Unlock()
	r.at = append(r.at, t)
}

// next forgets the times not after now and returns the earliest of the others, or the
// zero time.
func (r *retries) next(now time.Time) time.Time {
	r.mu.Lock()
	defer r.mu.Unlock()
	r.at = slices.DeleteFunc(r.at, func(t time.Time) bool { return !t.After(now) })
	var first time.Time
	for _, t := range r.at {
		if first.IsZero() || t.Before(first) {
			first = t
		}
	}
	return first
}

// notifier wakes every goroutine waiting on the current channel; waiters take the
// channel before checking the queue, so a wake-up between check and wait is not lost.
type notifier struct {
	mu sync.Mutex
	ch chan struct{}
}

func newNotifier() notifier { return notifier{ch: make(chan struct{})} }

func (n *notifier) wait() <-chan struct{} {
	n.mu.Lock()
	defer n.mu.Unlock()
	return n.ch
}

func (n *notifier) broadcast() {
	n.mu.Lock()
	defer n.mu.Unlock()
	close(n.ch)
	n.ch = make(chan struct{})
}
