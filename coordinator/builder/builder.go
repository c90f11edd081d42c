// Package builder is the coordinator's own worker for the build and merge phases: it
// leases BUILD and MERGE tasks through the same task service as the farm's workers (so
// leases, epochs and expiry protect it like any worker). A build reads the emission
// shards the lease names and merges them with photonmap.BuildTo into a kd-tree snapshot
// written to a file in the scratch folder, then streamed from it into the blob store; a
// merge reads the round's snapshot and irradiance shards and streams the snapshot with
// irradiance (photonmap.MergeIrradianceTo) straight into the blob store. Either completes
// the task with the result as "photons.snapshot".
//
// Inputs are read through the blob store's checked reader, record by record, and outputs
// are never held whole: a build's memory is its working records (24 bytes a photon of the
// largest map), a merge's a few buffers (docs/photon-snapshot.md).
// How a failure is reported:
//   - an input missing from the blob store or damaged there: lost input, naming the blob
//     and what it holds ("the global photon shard of paths 0+100000 of round 1");
//   - malformed shards, or more photons than a snapshot may hold
//     (scene_limits.max_snapshot_photons, saying which setting to lower): bad input;
//
// both fail the job at once (another attempt would read the same bytes). Anything else is
// transient.
package builder

import (
	"context"
	"errors"
	"fmt"
	"io"
	"log/slog"
	"os"
	"runtime/debug"
	"time"

	"photonfarm/contract/rules"
	"photonfarm/contract/tasks"
	"photonfarm/coordinator/blobstore"
	"photonfarm/coordinator/errs"
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
	// Build merges shards into a snapshot written to out and returns its size; by default
	// photonmap.BuildTo with the contract's max_snapshot_photons.
	Build func(out photonmap.Output, shards []photonmap.Source) (int64, error)
	// Merge writes a snapshot of snapshotSize bytes with the irradiance shards added to w;
	// photonmap.MergeIrradianceTo by default.
	Merge func(w io.Writer, snapshot photonmap.Source, snapshotSize int64, shards []photonmap.Source) (int64, error)
	// ScratchDir is the folder a build writes its snapshot file in before storing it (as
	// large as the snapshot; removed once stored), made when a build first needs it (a
	// coordinator on a read-only data folder still starts): os.TempDir() by default.
	ScratchDir string
	// WorkerID is the name the builder's leases go under (DefaultWorkerID by default).
	WorkerID string
	// HeartbeatInterval is how often a held lease is extended (1s by default); it must be
	// well below the lease duration.
	HeartbeatInterval time.Duration
	Logger            *slog.Logger
}

// MaxSnapshotPhotons is the contract's limit on the photons of one snapshot.
var MaxSnapshotPhotons = int(rules.Scene.GetMaxSnapshotPhotons())

// Builder runs build tasks one at a time. Create it with New and run it with Run.
type Builder struct {
	cfg Config
	log *slog.Logger
}

// New returns a Builder with cfg's defaults filled in.
func New(cfg Config) *Builder {
	if cfg.Build == nil {
		cfg.Build = func(out photonmap.Output, shards []photonmap.Source) (int64, error) {
			return photonmap.BuildTo(out, shards, MaxSnapshotPhotons)
		}
	}
	if cfg.Merge == nil {
		cfg.Merge = photonmap.MergeIrradianceTo
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
	inputs := tasks.Inputs(l.GetTask())
	switch spec := l.GetTask().GetSpec().(type) {
	case *pb.Task_BuildPhotonMap:
		out, err = b.build(taskCtx, spec.BuildPhotonMap, inputs)
	case *pb.Task_MergeIrradiance:
		out, err = b.merge(taskCtx, inputs)
	default:
		err = errs.E(errs.InvalidArgument, "the coordinator's builder cannot do task %s (%T)", ref.TaskID, spec)
	}
	if cause := context.Cause(taskCtx); cause != nil {
		b.log.Info("builder: build abandoned", "task", ref.TaskID, "why", cause)
		return
	}
	if err != nil {
		kind := failureKind(err)
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

// failureKind is how a build's error is reported: a lost input as lost, a full disk as
// resource exhaustion (blaming no worker), a malformed input or one over a limit as bad
// input (both permanent), anything else as transient.
func failureKind(err error) pb.FailureKind {
	switch {
	case errors.As(err, new(*blobstore.LostError)):
		return pb.FailureKind_FAILURE_KIND_LOST_INPUT
	case blobstore.IsDiskFull(err):
		return pb.FailureKind_FAILURE_KIND_RESOURCE_EXHAUSTED
	case errors.As(err, new(*photonmap.TooManyPhotons)), errs.Is(err, errs.InvalidArgument), errs.Is(err, errs.ResourceExhausted):
		return pb.FailureKind_FAILURE_KIND_BAD_INPUT
	}
	return pb.FailureKind_FAILURE_KIND_TRANSIENT
}

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

// build reads the shards, merges them into a snapshot file in the scratch folder and
// stores it from there.
func (b *Builder) build(ctx context.Context, spec *pb.BuildPhotonMapSpec, inputs []tasks.Input) (*pb.Artifact, error) {
	if b.cfg.ScratchDir != "" {
		if err := os.MkdirAll(b.cfg.ScratchDir, 0o755); err != nil {
			return nil, fmt.Errorf("build photon map: %w", err)
		}
	}
	f, err := os.CreateTemp(b.cfg.ScratchDir, "snapshot-*")
	if err != nil {
		return nil, fmt.Errorf("build photon map: %w", err)
	}
	// Unlinked at once: the file lives as long as it is open, so a coordinator killed
	// mid-build leaves no snapshot-sized file behind.
	os.Remove(f.Name())
	defer f.Close()
	size, err := b.cfg.Build(f, b.sources(ctx, inputs))
	// The working records are garbage now: give them back to the system at once rather
	// than after minutes, so the store, the merge and a container's memory limit do not
	// count them.
	debug.FreeOSMemory()
	var many *photonmap.TooManyPhotons
	if errors.As(err, &many) {
		return nil, tooManyPhotons(many, spec.GetShards()[many.Shard].GetSpec(), inputs[many.Shard])
	}
	if err != nil {
		return nil, named(inputs, "shards", 0, fmt.Errorf("build photon map: %w", err))
	}
	return b.store(ctx, io.NewSectionReader(f, 0, size), size)
}

// tooManyPhotons says, for people, that a build stopped at shard (emitted as spec) because
// the snapshot would hold more photons than the contract allows, and which setting lowers
// the count.
func tooManyPhotons(e *photonmap.TooManyPhotons, spec *pb.EmitPhotonsSpec, shard tasks.Input) error {
	setting := "photons." + tasks.MapName(spec.GetMap()) + "_photons"
	return &errs.Error{Kind: errs.InvalidArgument, Message: fmt.Sprintf(
		"the photon maps store more than the %d photons a snapshot may hold (scene_limits.max_snapshot_photons): "+
			"the %s map's shards up to %s store %d photons from %d paths (%.3g a path); lower %s",
		e.Limit, tasks.MapName(spec.GetMap()), shard.What, e.MapPhotons, e.MapPaths, float64(e.MapPhotons)/float64(max(e.MapPaths, 1)), setting)}
}

// merge reads the snapshot and the irradiance shards and streams the snapshot with
// irradiance into the blob store as it is made. The first input is the snapshot
// (tasks.Inputs), the others the shards.
func (b *Builder) merge(ctx context.Context, inputs []tasks.Input) (*pb.Artifact, error) {
	if len(inputs) == 0 || inputs[0].Artifact.GetName() != tasks.ArtifactName(pb.ArtifactKind_ARTIFACT_KIND_PHOTON_SNAPSHOT) {
		return nil, errs.E(errs.InvalidArgument, "merge_irradiance names no photon_snapshot")
	}
	sources := b.sources(ctx, inputs)
	r, w := io.Pipe()
	merged := make(chan error, 1)
	go func() {
		_, err := b.cfg.Merge(w, sources[0], inputs[0].Artifact.GetSizeBytes(), sources[1:])
		w.CloseWithError(err) // nil: the end of the snapshot
		merged <- err
	}()
	out, err := b.store(ctx, r, -1)
	r.CloseWithError(errStoreStopped) // a merge still writing stops
	if merr := <-merged; merr != nil && !errors.Is(merr, errStoreStopped) {
		return nil, named(inputs, "irradiance_shards", 1, fmt.Errorf("merge irradiance: %w", merr))
	}
	return out, err
}

// errStoreStopped ends a merge whose output the blob store stopped reading (it failed).
var errStoreStopped = errors.New("the blob store stopped reading the merged snapshot")

// named puts what the input holds before a malformed-input error that names it as
// list[i] (inputs[first+i]).
func named(inputs []tasks.Input, list string, first int, err error) error {
	var e *errs.Error
	var i int
	if errors.As(err, &e) {
		if _, serr := fmt.Sscanf(e.Field, list+"[%d]", &i); serr == nil && first+i < len(inputs) {
			return fmt.Errorf("%s: %w", inputs[first+i].What, err)
		}
	}
	return err
}

// store streams a snapshot of size bytes (-1: not known in advance) into the blob store
// as the task's "photons.snapshot".
func (b *Builder) store(ctx context.Context, snap io.Reader, size int64) (*pb.Artifact, error) {
	if err := ctx.Err(); err != nil {
		return nil, err
	}
	info, err := b.cfg.Blobs.Put(ctx, snap, size, "")
	if err != nil {
		return nil, fmt.Errorf("store photon snapshot: %w", err)
	}
	return &pb.Artifact{Name: tasks.ArtifactName(pb.ArtifactKind_ARTIFACT_KIND_PHOTON_SNAPSHOT), Digest: info.Digest, SizeBytes: info.Size}, nil
}

// sources opens each input through the blob store's checked reader; an input that is
// missing, of another size than its artifact says, or damaged (found at its end) is a
// *blobstore.LostError naming what it holds.
func (b *Builder) sources(ctx context.Context, inputs []tasks.Input) []photonmap.Source {
	out := make([]photonmap.Source, len(inputs))
	for i, in := range inputs {
		d := in.Artifact.GetDigest()
		out[i] = func() (io.ReadCloser, error) {
			if err := ctx.Err(); err != nil {
				return nil, err
			}
			r, info, err := b.cfg.Blobs.Open(ctx, d)
			if err != nil {
				return nil, blobstore.Lost(in.What, d, err)
			}
			if info.Size != in.Artifact.GetSizeBytes() {
				r.Close()
				return nil, blobstore.Lost(in.What, d, errs.E(errs.DataLoss, "blob %s has %d bytes, the task says %d", d, info.Size, in.Artifact.GetSizeBytes()))
			}
			return lostReader{r, in.What, d}, nil
		}
	}
	return out
}

// lostReader names the input a blob holds in the errors of reading it.
type lostReader struct {
	io.ReadCloser
	what, digest string
}

func (r lostReader) Read(p []byte) (int, error) {
	n, err := r.ReadCloser.Read(p)
	if err != nil && !errors.Is(err, io.EOF) {
		err = blobstore.Lost(r.what, r.digest, err)
	}
	return n, err
}
