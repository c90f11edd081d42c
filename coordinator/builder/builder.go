// Package builder is the coordinator's own worker for the build and merge phases: it
// leases BUILD and MERGE tasks through the same task service as the farm's workers (so
// leases, epochs and expiry protect it like any worker). A build downloads the emission
// shards the lease names and merges them with photonmap.Build into a kd-tree snapshot; a
// merge downloads the round's snapshot and irradiance shards and adds the irradiance with
// photonmap.MergeIrradiance. Either stores the result in the blob store and completes the
// task with it as "photons.snapshot". Malformed shards (or a malformed snapshot) fail the
// task as bad input, which fails the job at once: another attempt would read the same
// bytes. Anything else that goes wrong (a blob that cannot be read) is transient.
package builder

import (
	"bytes"
	"context"
	"errors"
	"fmt"
	"io"
	"log/slog"
	"time"

	"photonfarm/contract/tasks"
	"photonfarm/coordinator/blobstore"
	"photonfarm/coordinator/photonmap"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// Tasks is what the builder needs of the task service: service.Service, as the
// coordinator's wiring asserts (the builder does not import the service, which would
// tie the coordinator's own worker to the gRPC layer).
type Tasks interface {
	Lease(ctx context.Context, workerID string, phases []pb.Phase, wait time.Duration) (*pb.LeaseTaskResponse, error)
	Extend(ctx context.Context, workerID string, held []*pb.HeldLease) ([]*pb.Lease, []*pb.HeldLease, error)
	Complete(ctx context.Context, ref store.LeaseRef, outputs []*pb.Artifact) error
	Fail(ctx context.Context, ref store.LeaseRef, f store.Failure) error
}

// Blobs is what the builder needs of the blob store.
type Blobs interface {
	Open(ctx context.Context, digest string) (io.ReadCloser, blobstore.Info, error)
	Put(ctx context.Context, r io.Reader, size int64, digest string) (blobstore.Info, error)
}

var _ Blobs = (*blobstore.Store)(nil)

// Defaults for Config.
const (
	DefaultWorkerID = "coordinator-builder"
	// leaseWait is how long one lease call waits for a build to be queued.
	leaseWait = 10 * time.Second
	// retryAfter is the pause after the task service failed unexpectedly.
	retryAfter = time.Second
)

// Config wires a Builder. Tasks and Blobs are required.
type Config struct {
	Tasks Tasks
	Blobs Blobs
	// Build merges shards into a snapshot; photonmap.Build by default.
	Build func([]photonmap.Shard) ([]byte, error)
	// Merge adds irradiance shards to a snapshot; photonmap.MergeIrradiance by default.
	Merge func(snapshot []byte, shards [][]byte) ([]byte, error)
	// WorkerID is the name the builder's leases go under (DefaultWorkerID by default).
	WorkerID string
	// HeartbeatInterval is how often a held lease is extended (1s by default); it must be
	// well below the lease duration.
	HeartbeatInterval time.Duration
	Logger            *slog.Logger
}

// Builder runs build tasks one at a time. Create it with New and run it with Run.
type Builder struct {
	cfg Config
	log *slog.Logger
}

// New returns a Builder with cfg's defaults filled in.
func New(cfg Config) *Builder {
	if cfg.Build == nil {
		cfg.Build = photonmap.Build
	}
	if cfg.Merge == nil {
		cfg.Merge = photonmap.MergeIrradiance
	}
	if cfg.WorkerID == "" {
		cfg.WorkerID = DefaultWorkerID
	}
	if cfg.HeartbeatInterval <= 0 {
		cfg.HeartbeatInterval = time.Second
	}
	if cfg.Logger == nil {
		cfg.Logger = slog.New(slog.DiscardHandler)
	}
	return &Builder{cfg: cfg, log: cfg.Logger}
}

// Run leases and performs build tasks until ctx is cancelled; it then returns nil. A build
// in progress when ctx is cancelled is abandoned (its lease expires).
func (b *Builder) Run(ctx context.Context) error {
	for ctx.Err() == nil {
		l, err := b.cfg.Tasks.Lease(ctx, b.cfg.WorkerID, store.BuilderPhases, leaseWait)
		if err != nil {
			if ctx.Err() != nil {
				break
			}
			b.log.Error("builder: lease", "err", err)
			sleep(ctx, retryAfter)
			continue
		}
		if l.GetLease() != nil {
			b.runTask(ctx, l)
		}
	}
	return nil
}

func sleep(ctx context.Context, d time.Duration) {
	t := time.NewTimer(d)
	defer t.Stop()
	select {
	case <-ctx.Done():
	case <-t.C:
	}
}

// runTask performs one leased build and reports it, keeping the lease alive meanwhile.
func (b *Builder) runTask(ctx context.Context, l *pb.LeaseTaskResponse) {
	ref := store.LeaseRef{WorkerID: b.cfg.WorkerID, TaskID: l.GetLease().GetTaskId(), Epoch: l.GetLease().GetEpoch()}
	start := time.Now()
	taskCtx, cancel := context.WithCancelCause(ctx)
	defer cancel(nil)
	go b.heartbeat(taskCtx, ref, cancel)

	var out *pb.Artifact
	var err error
	switch spec := l.GetTask().GetSpec().(type) {
	case *pb.Task_BuildPhotonMap:
		out, err = b.build(taskCtx, spec.BuildPhotonMap)
	case *pb.Task_MergeIrradiance:
		out, err = b.merge(taskCtx, spec.MergeIrradiance)
	default:
		err = badInput{fmt.Errorf("the coordinator's builder cannot do task %s (%T)", ref.TaskID, spec)}
	}
	if cause := context.Cause(taskCtx); cause != nil {
		b.log.Info("builder: build abandoned", "task", ref.TaskID, "why", cause)
		return
	}
	if err != nil {
		kind := pb.FailureKind_FAILURE_KIND_TRANSIENT
		if errors.As(err, new(badInput)) {
			kind = pb.FailureKind_FAILURE_KIND_BAD_INPUT
		}
		b.log.Warn("builder: build failed", "task", ref.TaskID, "kind", kind.String(), "err", err)
		if ferr := b.cfg.Tasks.Fail(ctx, ref, store.Failure{Message: err.Error(), Kind: kind}); ferr != nil {
			b.log.Error("builder: reporting failure", "task", ref.TaskID, "err", ferr)
		}
		return
	}
	if err := b.cfg.Tasks.Complete(ctx, ref, []*pb.Artifact{out}); err != nil {
		b.log.Error("builder: reporting completion", "task", ref.TaskID, "err", err)
		return
	}
	b.log.Info("photon map built", "task", ref.TaskID, "phase", l.GetTask().GetPhase().String(),
		"bytes", out.GetSizeBytes(), "snapshot", out.GetDigest(), "took", time.Since(start).Round(time.Millisecond))
}

// badInput marks an error in what the task's inputs hold (a malformed shard): every
// attempt would fail the same way.
type badInput struct{ error }

func (e badInput) Unwrap() error { return e.error }

// errLeaseLost is the cause of a build's cancellation when its lease was revoked.
var errLeaseLost = errors.New("lease lost")

// heartbeat extends the lease every HeartbeatInterval until ctx ends; if the lease is
// revoked it cancels the build.
func (b *Builder) heartbeat(ctx context.Context, ref store.LeaseRef, cancel context.CancelCauseFunc) {
	t := time.NewTicker(b.cfg.HeartbeatInterval)
	defer t.Stop()
	held := []*pb.HeldLease{{TaskId: ref.TaskID, Epoch: ref.Epoch}}
	for {
		select {
		case <-ctx.Done():
			return
		case <-t.C:
		}
		_, revoked, err := b.cfg.Tasks.Extend(ctx, ref.WorkerID, held)
		if err != nil {
			if ctx.Err() == nil {
				b.log.Warn("builder: heartbeat", "task", ref.TaskID, "err", err)
			}
			continue
		}
		if len(revoked) > 0 {
			cancel(errLeaseLost)
			return
		}
	}
}

// build downloads the shards, merges them and stores the snapshot.
func (b *Builder) build(ctx context.Context, spec *pb.BuildPhotonMapSpec) (*pb.Artifact, error) {
	shards := make([]photonmap.Shard, len(spec.GetShards()))
	for i, s := range spec.GetShards() {
		data, err := b.download(ctx, s.GetShard())
		if err != nil {
			return nil, fmt.Errorf("shard %d (photons %d+%d of the %s map): %w", i,
				s.GetSpec().GetFirstPhoton(), s.GetSpec().GetPhotonCount(), mapName(s.GetSpec().GetMap()), err)
		}
		shards[i].Data = data
	}
	snap, err := b.cfg.Build(shards)
	if err != nil {
		return nil, badInput{fmt.Errorf("build photon map: %w", err)}
	}
	return b.store(ctx, snap)
}

// merge downloads the snapshot and the irradiance shards, merges them and stores the
// snapshot with irradiance.
func (b *Builder) merge(ctx context.Context, spec *pb.MergeIrradianceSpec) (*pb.Artifact, error) {
	snap, err := b.download(ctx, spec.GetPhotonSnapshot())
	if err != nil {
		return nil, fmt.Errorf("photon snapshot: %w", err)
	}
	shards := make([][]byte, len(spec.GetIrradianceShards()))
	for i, a := range spec.GetIrradianceShards() {
		if shards[i], err = b.download(ctx, a); err != nil {
			return nil, fmt.Errorf("irradiance shard %d: %w", i, err)
		}
	}
	merged, err := b.cfg.Merge(snap, shards)
	if err != nil {
		return nil, badInput{fmt.Errorf("merge irradiance: %w", err)}
	}
	return b.store(ctx, merged)
}

// store puts a snapshot in the blob store as the task's "photons.snapshot".
func (b *Builder) store(ctx context.Context, snap []byte) (*pb.Artifact, error) {
	if err := ctx.Err(); err != nil {
		return nil, err
	}
	info, err := b.cfg.Blobs.Put(ctx, bytes.NewReader(snap), int64(len(snap)), "")
	if err != nil {
		return nil, fmt.Errorf("store photon snapshot: %w", err)
	}
	return &pb.Artifact{Name: tasks.ArtifactName(pb.ArtifactKind_ARTIFACT_KIND_PHOTON_SNAPSHOT), Digest: info.Digest, SizeBytes: info.Size}, nil
}

func (b *Builder) download(ctx context.Context, a *pb.Artifact) ([]byte, error) {
	r, info, err := b.cfg.Blobs.Open(ctx, a.GetDigest())
	if err != nil {
		return nil, err
	}
	defer r.Close()
	if info.Size != a.GetSizeBytes() {
		return nil, fmt.Errorf("blob %s has %d bytes, the task says %d", a.GetDigest(), info.Size, a.GetSizeBytes())
	}
	data := make([]byte, info.Size)
	if _, err := io.ReadFull(r, data); err != nil {
		return nil, fmt.Errorf("read blob %s: %w", a.GetDigest(), err)
	}
	return data, nil
}

func mapName(k pb.PhotonMapKind) string {
	switch k {
	case pb.PhotonMapKind_PHOTON_MAP_KIND_GLOBAL:
		return "global"
	case pb.PhotonMapKind_PHOTON_MAP_KIND_CAUSTIC:
		return "caustic"
	}
	return k.String()
}
