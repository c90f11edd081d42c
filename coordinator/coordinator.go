// Package coordinator assembles the farm's coordinator: the gRPC services over a store, a
// content-addressed blob store and an event broker, plus the loop that requeues expired
// leases and the builder that merges photon shards (the build phase). cmd/farm calls New
// and Serve.
package coordinator

import (
	"context"
	"crypto/tls"
	"errors"
	"fmt"
	"io"
	"log/slog"
	"net"
	"net/http"
	"net/url"
	"path/filepath"
	"time"

	"github.com/redis/go-redis/v9"
	"google.golang.org/grpc"
	"google.golang.org/grpc/credentials"

	"photonfarm/coordinator/auth"
	"photonfarm/coordinator/blobstore"
	"photonfarm/coordinator/builder"
	"photonfarm/coordinator/clock"
	"photonfarm/coordinator/events"
	"photonfarm/coordinator/metrics"
	"photonfarm/coordinator/retention"
	"photonfarm/coordinator/service"
	"photonfarm/coordinator/store"
	"photonfarm/coordinator/store/memstore"
	"photonfarm/coordinator/store/redisstore"
)

// Defaults for Config.
const (
	DefaultLeaseDuration = store.DefaultLeaseDuration
	DefaultStuckTimeout  = store.DefaultStuckTimeout
	DefaultRetention     = retention.DefaultRetention
	DefaultBlobGrace     = retention.DefaultBlobGrace
	// StopTimeout is how long Serve waits for RPCs in flight after ctx is cancelled
	// before closing connections.
	StopTimeout = 10 * time.Second
)

// Config configures a Coordinator.
type Config struct {
	// DataDir holds the blob store (DataDir/blobs) unless BlobURL names another, and the
	// builder's snapshot files while they are built (DataDir/scratch: as large as the
	// largest snapshot, docs/limits.md). Required.
	DataDir string
	// BlobURL, if set, names the blob store instead (blobstore.Open): file:///folder, or
	// s3://bucket?endpoint=...&region=... for an S3-compatible object store that several
	// coordinators can share (credentials from the AWS SDK's environment variables or
	// credentials file, never the URL).
	BlobURL string
	// LeaseDuration is how long a task lease lasts without a heartbeat (default 15s).
	LeaseDuration time.Duration
	// HeartbeatInterval is how often workers are told to heartbeat (default
	// LeaseDuration/4).
	HeartbeatInterval time.Duration
	// StuckTimeout: a lease whose progress (HeldLease.progress) has not grown for this
	// long is revoked at a heartbeat and counted as a failed attempt (default 10m).
	StuckTimeout time.Duration
	// Retention is how long an ended job is kept before it is deleted with its tasks
	// (default a week), and BlobGrace how old a blob no job refers to must be before it
	// is deleted (default a day): package retention.
	Retention, BlobGrace time.Duration
	// Clock defaults to the system clock.
	Clock clock.Clock
	// Logger defaults to slog.Default().
	Logger *slog.Logger

	// ClientTokens and WorkerTokens are the bearer tokens of the two roles (package
	// auth): a client token may call JobService and BlobService, a worker token
	// WorkerService and BlobService. When both are empty authentication is OFF and any
	// caller may do anything; that is only safe on loopback or a trusted network.
	ClientTokens, WorkerTokens []string
	// TLS, if not nil, serves gRPC over TLS with this configuration (it needs a
	// certificate); nil serves plaintext. MinVersion defaults to TLS 1.2.
	TLS *tls.Config

	// RedisURL, if set ("redis://[:password@]host:port/db", or rediss:// for TLS), keeps
	// jobs, tasks and leases in Redis (package redisstore): they survive a restart of the
	// coordinator, and several coordinators may share them. Empty keeps them in this
	// process (memstore), lost when it exits.
	RedisURL string
	// RedisPrefix is put before every key (default "farm:"), so that farms can share a
	// Redis.
	RedisPrefix string
}

// The service is the builder's task service: the builder declares what it needs of it
// rather than importing it.
var _ builder.Tasks = (*service.Service)(nil)

// openBlobs opens the blob store cfg.BlobURL names, else the folder DataDir/blobs.
func openBlobs(cfg Config) (*blobstore.Store, error) {
	if cfg.BlobURL == "" {
		return blobstore.New(filepath.Join(cfg.DataDir, "blobs"), 0)
	}
	return blobstore.Open(context.Background(), cfg.BlobURL, 0)
}

// DefaultRedisPrefix is Config.RedisPrefix's default.
const DefaultRedisPrefix = "farm:"

// Coordinator is the assembled coordinator. Create it with New and run it with Serve.
type Coordinator struct {
	cfg     Config
	auth    *auth.Authenticator
	log     *slog.Logger
	store   store.Store
	closers []io.Closer // of the store's and the blob store's connections; closed when Serve returns
	metrics *metrics.Metrics
	svc     *service.Service
	builder *builder.Builder
	sweeper *retention.Sweeper
	blobs   *blobstore.Store
}

// New checks cfg, opens the blob store under DataDir and the store (Redis if
// cfg.RedisURL is set, else in memory) and builds the services. Calls are authenticated
// if cfg has tokens (package auth) and encrypted if cfg.TLS is set.
func New(cfg Config) (*Coordinator, error) {
	if cfg.DataDir == "" {
		return nil, errors.New("coordinator: Config.DataDir is required")
	}
	if cfg.LeaseDuration < 0 || cfg.HeartbeatInterval < 0 || cfg.StuckTimeout < 0 || cfg.Retention < 0 || cfg.BlobGrace < 0 {
		return nil, errors.New("coordinator: durations must not be negative")
	}
	if cfg.LeaseDuration == 0 {
		cfg.LeaseDuration = DefaultLeaseDuration
	}
	if cfg.HeartbeatInterval == 0 {
		cfg.HeartbeatInterval = cfg.LeaseDuration / 4
	}
	if cfg.HeartbeatInterval >= cfg.LeaseDuration {
		return nil, fmt.Errorf("coordinator: HeartbeatInterval %v must be shorter than LeaseDuration %v", cfg.HeartbeatInterval, cfg.LeaseDuration)
	}
	if cfg.Clock == nil {
		cfg.Clock = clock.Real{}
	}
	if cfg.Logger == nil {
		cfg.Logger = slog.Default()
	}
	authn, err := auth.New(cfg.ClientTokens, cfg.WorkerTokens)
	if err != nil {
		return nil, fmt.Errorf("coordinator: %w", err)
	}
	if cfg.TLS != nil {
		if len(cfg.TLS.Certificates) == 0 && cfg.TLS.GetCertificate == nil && cfg.TLS.GetConfigForClient == nil {
			return nil, errors.New("coordinator: Config.TLS has no certificate")
		}
		cfg.TLS = cfg.TLS.Clone()
		if cfg.TLS.MinVersion == 0 {
			cfg.TLS.MinVersion = tls.VersionTLS12
		}
	}
	blobs, err := openBlobs(cfg)
	if err != nil {
		return nil, fmt.Errorf("coordinator: %w", err)
	}
	st, workers, closers, err := openStore(cfg)
	if err != nil {
		blobs.Close()
		return nil, err
	}
	closers = append(closers, blobs)
	m := metrics.New(metrics.StoreCounts(st))
	svc := service.New(service.Config{
		Store:             st,
		Metrics:           m,
		Blobs:             blobs,
		Events:            events.NewBroker(0),
		Workers:           workers,
		Clock:             cfg.Clock,
		Logger:            cfg.Logger,
		LeaseDuration:     cfg.LeaseDuration,
		HeartbeatInterval: cfg.HeartbeatInterval,
	})
	b := builder.New(builder.Config{
		Tasks:             svc,
		Blobs:             blobs,
		ScratchDir:        filepath.Join(cfg.DataDir, "scratch"),
		HeartbeatInterval: cfg.HeartbeatInterval,
		Logger:            cfg.Logger,
	})
	sw := retention.New(retention.Config{Store: st, Blobs: blobs, Clock: cfg.Clock, Logger: cfg.Logger,
		Retention: cfg.Retention, BlobGrace: cfg.BlobGrace})
	return &Coordinator{cfg: cfg, auth: authn, log: cfg.Logger, store: st, closers: closers, metrics: m, svc: svc, builder: b, sweeper: sw, blobs: blobs}, nil
}

// openStore opens the store cfg names, its worker registry (in Redis, the one every
// replica on that Redis shares), and what must be closed after them.
func openStore(cfg Config) (store.Store, store.Workers, []io.Closer, error) {
	opts := store.Options{Clock: cfg.Clock, LeaseDuration: cfg.LeaseDuration, StuckTimeout: cfg.StuckTimeout}
	if cfg.RedisURL == "" {
		return memstore.New(opts), memstore.NewWorkers(), nil, nil
	}
	ropts, err := redis.ParseURL(cfg.RedisURL)
	if err != nil {
		return nil, nil, nil, fmt.Errorf("coordinator: Config.RedisURL: %w", err)
	}
	prefix := cfg.RedisPrefix
	if prefix == "" {
		prefix = DefaultRedisPrefix
	}
	rdb := redis.NewClient(ropts)
	ctx, cancel := context.WithTimeout(context.Background(), 10*time.Second)
	defer cancel()
	st, err := redisstore.New(ctx, rdb, prefix, opts)
	if err != nil {
		rdb.Close()
		return nil, nil, nil, fmt.Errorf("coordinator: Redis at %s: %w", ropts.Addr, err)
	}
	return st, st.Workers(), []io.Closer{rdb}, nil
}

// MetricsHandler serves the coordinator's Prometheus metrics.
func (c *Coordinator) MetricsHandler() http.Handler { return c.metrics.Handler() }

// Serve serves JobService, WorkerService and BlobService on lis (behind the token check
// and TLS, if configured), sweeps expired leases and
// runs the photon map builder until ctx is cancelled; it then stops gracefully, closing
// connections after StopTimeout. It returns nil after a stop caused by ctx.
func (c *Coordinator) Serve(ctx context.Context, lis net.Listener) error {
	defer func() {
		for _, cl := range c.closers {
			cl.Close()
		}
	}()
	// Metrics first, so that they time the whole call and see the final status code.
	opts := append([]grpc.ServerOption{
		grpc.ChainUnaryInterceptor(c.metrics.UnaryServerInterceptor),
		grpc.ChainStreamInterceptor(c.metrics.StreamServerInterceptor),
	}, c.auth.ServerOptions(c.metrics.CallRefused)...)
	if c.cfg.TLS != nil {
		opts = append(opts, grpc.Creds(credentials.NewTLS(c.cfg.TLS)))
	}
	srv := c.svc.NewGRPCServer(opts...)
	ctx, cancel := context.WithCancel(ctx)
	defer cancel()

	sweepDone := make(chan struct{})
	go func() {
		defer close(sweepDone)
		c.sweep(ctx)
	}()
	buildDone := make(chan struct{})
	go func() {
		defer close(buildDone)
		_ = c.builder.Run(ctx)
	}()
	followDone := make(chan struct{})
	go func() {
		defer close(followDone)
		if feed, ok := c.store.(store.Feed); ok {
			_ = c.svc.FollowReplicas(ctx, feed)
		}
	}()
	retainDone := make(chan struct{})
	go func() {
		defer close(retainDone)
		c.sweeper.Run(ctx)
	}()

	served := make(chan error, 1)
	go func() { served <- srv.Serve(lis) }()
	c.log.Info("coordinator serving", "addr", lis.Addr().String(), "data_dir", c.cfg.DataDir,
		"lease_duration", c.cfg.LeaseDuration, "heartbeat_interval", c.cfg.HeartbeatInterval,
		"auth", c.AuthEnabled(), "tls", c.cfg.TLS != nil, "store", c.storeName(), "blobs", c.blobs.String())

	var err error
	select {
	case err = <-served: // the listener failed
		cancel()
	case <-ctx.Done():
		c.log.Info("coordinator stopping")
		c.svc.Shutdown()
		stopGracefully(srv, StopTimeout)
		err = <-served
		if errors.Is(err, grpc.ErrServerStopped) {
			err = nil
		}
	}
	<-sweepDone
	<-buildDone
	<-followDone
	<-retainDone
	if err != nil {
		return fmt.Errorf("coordinator: %w", err)
	}
	c.log.Info("coordinator stopped")
	return nil
}

// storeName says where state lives, for the log (without a Redis password).
func (c *Coordinator) storeName() string {
	if c.cfg.RedisURL == "" {
		return "memory"
	}
	if u, err := url.Parse(c.cfg.RedisURL); err == nil {
		return "redis " + u.Redacted()
	}
	return "redis"
}

// AuthEnabled reports whether calls need a token (Config has tokens).
func (c *Coordinator) AuthEnabled() bool { return c.auth.Enabled() }

func stopGracefully(srv *grpc.Server, timeout time.Duration) {
	done := make(chan struct{})
	go func() {
		srv.GracefulStop()
		close(done)
	}()
	t := time.NewTimer(timeout)
	defer t.Stop()
	select {
	case <-done:
	case <-t.C:
		srv.Stop()
		<-done
	}
}

// sweep requeues expired leases, forgets workers silent for ForgetAfterLeases lease
// durations, and fails the jobs every live worker is blocked from (a worker lost since the
// last block may have been the only one left that could run them), a few times per lease
// duration.
func (c *Coordinator) sweep(ctx context.Context) {
	every := min(max(c.cfg.LeaseDuration/10, 10*time.Millisecond), time.Second)
	t := time.NewTicker(every)
	defer t.Stop()
	for {
		select {
		case <-ctx.Done():
			return
		case <-t.C:
			if err := c.svc.ExpireLeases(ctx); err != nil && ctx.Err() == nil {
				c.log.Error("expiring leases", "err", err)
			}
			if err := c.svc.ForgetSilentWorkers(ctx); err != nil && ctx.Err() == nil {
				c.log.Error("forgetting silent workers", "err", err)
			}
			if err := c.svc.FailBlockedJobs(ctx); err != nil && ctx.Err() == nil {
				c.log.Error("failing blocked jobs", "err", err)
			}
		}
	}
}
