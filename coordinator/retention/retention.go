// Package retention deletes what the farm no longer needs (docs/limits.md, "Retention"):
// jobs that ended more than a retention ago, with their tasks and rounds, and jobs a
// coordinator that died left half-made (store.Store.PurgeJobs, in bounded steps); then
// the blobs no remaining job refers to (scenes, meshes, reference images, shards,
// snapshots, tiles, images) once they are older than a grace period. The coordinator runs
// a Sweep when it starts and every Interval.
//
// A blob is referenced by a job if it is its scene, a mesh or the reference image its
// scene names, or an output of one of its tasks or of the job. Jobs made while a sweep
// runs are not seen by it; their blobs are kept because whoever records a reference
// touches the blob first (blobstore's collection protocol) and the sweep deletes only
// blobs not touched since its cutoff, now minus the grace: long enough for an upload to
// be followed by its submit.
package retention

import (
	"cmp"
	"context"
	"fmt"
	"io"
	"log/slog"
	"time"

	"google.golang.org/protobuf/proto"

	"photonfarm/contract/pages"
	"photonfarm/contract/scene"
	"photonfarm/coordinator/blobstore"
	"photonfarm/coordinator/clock"
	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// Defaults (docs/limits.md, "Retention").
const (
	// DefaultRetention is how long an ended job is kept: a week.
	DefaultRetention = 7 * 24 * time.Hour
	// DefaultBlobGrace is how old an unreferenced blob must be to be deleted: a day, far
	// longer than an upload takes to be followed by its submit or its completion.
	DefaultBlobGrace = 24 * time.Hour
	// DefaultAbandoned is how long a half-made job may go without growing before it is
	// deleted: its maker died (a submission that is still going stages a chunk of tasks
	// every few milliseconds).
	DefaultAbandoned = time.Hour
	// DefaultInterval is how often the coordinator sweeps.
	DefaultInterval = time.Hour
	// PurgeBudget is the most task records one PurgeJobs step deletes. A step of 1000 took
	// about 1.5 ms of Redis CPU on a quiet machine but once 20.6 ms on a busy one, over the
	// 20 ms that redisstore allows any one command; 500 halves what a step can cost.
	PurgeBudget = 500
	// listPage is the jobs or tasks read at a time while listing references.
	listPage = 1000
)

// Blobs is what a sweep needs of the blob store.
type Blobs interface {
	Open(ctx context.Context, digest string) (io.ReadCloser, blobstore.Info, error)
	Walk(ctx context.Context, fn func(blobstore.Entry) error) error
	DeleteUnused(ctx context.Context, digest string, before time.Time) (bool, error)
}

var _ Blobs = (*blobstore.Store)(nil)

// Config configures a Sweeper; zero durations select the defaults.
type Config struct {
	Store     store.Store
	Blobs     Blobs
	Clock     clock.Clock
	Logger    *slog.Logger
	Retention time.Duration
	BlobGrace time.Duration
	Abandoned time.Duration
	Interval  time.Duration
}

// Sweeper deletes ended jobs and unreferenced blobs.
type Sweeper struct{ cfg Config }

// New returns a Sweeper; Store and Blobs are required.
func New(cfg Config) *Sweeper {
	cfg.Clock = cmp.Or[clock.Clock](cfg.Clock, clock.Real{})
	if cfg.Logger == nil {
		cfg.Logger = slog.New(slog.DiscardHandler)
	}
	cfg.Retention = cmp.Or(cfg.Retention, DefaultRetention)
	cfg.BlobGrace = cmp.Or(cfg.BlobGrace, DefaultBlobGrace)
	cfg.Abandoned = cmp.Or(cfg.Abandoned, DefaultAbandoned)
	cfg.Interval = cmp.Or(cfg.Interval, DefaultInterval)
	return &Sweeper{cfg: cfg}
}

// Report is what a sweep deleted.
type Report struct {
	Jobs       int   // jobs deleted
	Blobs      int   // blobs deleted
	BlobBytes  int64 // their size
	Referenced int   // blobs the remaining jobs refer to
}

// Run sweeps now and every Interval until ctx is done, logging what each sweep did.
func (w *Sweeper) Run(ctx context.Context) {
	t := time.NewTicker(w.cfg.Interval)
	defer t.Stop()
	for {
		r, err := w.Sweep(ctx)
		switch {
		case ctx.Err() != nil:
			return
		case err != nil:
			w.cfg.Logger.Warn("retention sweep failed", "err", err)
		case r.Jobs > 0 || r.Blobs > 0:
			w.cfg.Logger.Info("retention sweep", "jobs_deleted", r.Jobs, "blobs_deleted", r.Blobs, "bytes_freed", r.BlobBytes, "blobs_kept", r.Referenced)
		}
		select {
		case <-t.C:
		case <-ctx.Done():
			return
		}
	}
}

// Sweep deletes the jobs past their retention, then the unreferenced blobs older than the
// grace period.
func (w *Sweeper) Sweep(ctx context.Context) (Report, error) {
	var r Report
	now := w.cfg.Clock.Now()
	for {
		p, err := w.cfg.Store.PurgeJobs(ctx, now.Add(-w.cfg.Retention), now.Add(-w.cfg.Abandoned), PurgeBudget)
		if err != nil {
			return r, err
		}
		r.Jobs += len(p.Deleted)
		if !p.More {
			break
		}
	}
	// The cutoff is taken before the references are listed (package comment).
	cutoff := now.Add(-w.cfg.BlobGrace)
	refs, err := w.references(ctx)
	if err != nil {
		return r, err
	}
	r.Referenced = len(refs)
	var old []blobstore.Entry
	err = w.cfg.Blobs.Walk(ctx, func(e blobstore.Entry) error {
		if e.ModTime.Before(cutoff) && !refs[e.Digest] {
			old = append(old, e)
		}
		return nil
	})
	if err != nil {
		return r, err
	}
	for _, e := range old {
		deleted, err := w.cfg.Blobs.DeleteUnused(ctx, e.Digest, cutoff)
		if err != nil {
			return r, err
		}
		if deleted {
			r.Blobs++
			r.BlobBytes += e.Size
		}
	}
	return r, nil
}

// references returns the digests of every blob a job in the store refers to.
func (w *Sweeper) references(ctx context.Context) (map[string]bool, error) {
	refs := map[string]bool{}
	add := func(as []*pb.Artifact) {
		for _, a := range as {
			refs[a.GetDigest()] = true
		}
	}
	return refs, pages.Each(func(token string) ([]*pb.Job, string, error) {
		return w.cfg.Store.ListJobs(ctx, listPage, token)
	}, func(j *pb.Job) (bool, error) {
		refs[j.GetSceneDigest()] = true
		add(j.GetOutputs())
		if err := w.sceneRefs(ctx, j, refs); err != nil {
			return false, err
		}
		err := pages.Each(func(token string) ([]*pb.Task, string, error) {
			return w.cfg.Store.ListTasks(ctx, j.GetId(), listPage, token)
		}, func(t *pb.Task) (bool, error) {
			add(t.GetOutputs())
			if l := t.GetLog(); l != nil {
				add([]*pb.Artifact{l})
			}
			return true, nil
		})
		if errs.Is(err, errs.NotFound) {
			return true, nil // deleted while listed
		}
		return err == nil, err
	})
}

// sceneRefs adds the blobs job j's scene names (meshes, reference image). A scene blob
// that is missing or undecodable names nothing more (the job fails when it needs it);
// any other failure to read it stops the sweep, which must not delete what it names.
func (w *Sweeper) sceneRefs(ctx context.Context, j *pb.Job, refs map[string]bool) error {
	r, _, err := w.cfg.Blobs.Open(ctx, j.GetSceneDigest())
	if errs.Is(err, errs.NotFound) {
		w.cfg.Logger.Warn("retention: the scene of a job is missing", "job", j.GetId(), "scene", j.GetSceneDigest())
		return nil
	}
	if err != nil {
		return fmt.Errorf("retention: scene %s of job %s: %w", j.GetSceneDigest(), j.GetId(), err)
	}
	defer r.Close()
	data, err := io.ReadAll(r)
	if err != nil {
		return fmt.Errorf("retention: read scene %s: %w", j.GetSceneDigest(), err)
	}
	sc := &pb.Scene{}
	if err := proto.Unmarshal(data, sc); err != nil {
		w.cfg.Logger.Warn("retention: scene of a job undecodable", "job", j.GetId(), "scene", j.GetSceneDigest(), "err", err)
		return nil
	}
	for _, f := range scene.Files(sc) {
		refs[f.Digest] = true
	}
	return nil
}
