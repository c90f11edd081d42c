package main

import (
	"context"
	"crypto/tls"
	"errors"
	"fmt"
	"io"
	"log/slog"
	"net"
	"net/http"
	"os"
	"path/filepath"
	"runtime/pprof"
	"strings"
	"time"

	"photonfarm/coordinator"
)

var coordinatorVerb = &verb{
	name:    "coordinator",
	args:    "[--listen ADDR] [--data-dir DIR] [--blobs URL] [--redis URL] [--metrics-listen ADDR] [--lease-duration D] [--stuck-timeout D] [--retention D] [--blob-grace D] [--client-token-file F] [--worker-token-file F] [--tls-cert F --tls-key F] [--cpu-profile F]",
	summary: "run a coordinator (gRPC: jobs, workers, blobs)",
	run:     runCoordinator,
}

func defaultDataDir() string {
	if d, err := os.UserCacheDir(); err == nil {
		return filepath.Join(d, "photonfarm", "coordinator")
	}
	return filepath.Join(os.TempDir(), "photonfarm-coordinator")
}

func runCoordinator(ctx context.Context, e *env, args []string) error {
	fs := newFlags("coordinator", e)
	listen := fs.String("listen", ":7070", "`address` to listen on, HOST:PORT (port 0 picks a free one)")
	dataDir := fs.String("data-dir", defaultDataDir(), "`folder` for the blob store and state")
	blobURL := fs.String("blobs", "", "keep blobs in the store at this `URL` (also $FARM_BLOB_URL): file:///folder, or s3://bucket?endpoint=URL&region=R for an S3-compatible object store, with credentials in $AWS_ACCESS_KEY_ID and $AWS_SECRET_ACCESS_KEY or $AWS_SHARED_CREDENTIALS_FILE; default: --data-dir/blobs")
	lease := fs.Duration("lease-duration", coordinator.DefaultLeaseDuration, "how long a task lease lasts without a heartbeat")
	heartbeat := fs.Duration("heartbeat-interval", 0, "how often workers heartbeat (0: a quarter of the lease duration)")
	stuck := fs.Duration("stuck-timeout", coordinator.DefaultStuckTimeout, "revoke a lease whose progress has not grown for this long, counting a failed attempt")
	retain := fs.Duration("retention", coordinator.DefaultRetention, "delete an ended job, with its tasks, this long after it ended")
	grace := fs.Duration("blob-grace", coordinator.DefaultBlobGrace, "delete a blob no job refers to once it is this old (untouched for this long)")
	logLevel := fs.String("log-level", "info", "log level: debug, info, warn, error")
	clientTokenFile := fs.String("client-token-file", "", "`file` of client tokens, one a line (# comments); also $FARM_CLIENT_TOKENS, comma-separated")
	workerTokenFile := fs.String("worker-token-file", "", "`file` of worker tokens, one a line (# comments); also $FARM_WORKER_TOKENS, comma-separated")
	tlsCert := fs.String("tls-cert", "", "serve gRPC over TLS with this PEM certificate `file` (needs --tls-key)")
	tlsKey := fs.String("tls-key", "", "PEM private key `file` of --tls-cert")
	redisURL := fs.String("redis", "", "keep jobs, tasks and leases in Redis at this `URL` (redis://host:6379/0; also $FARM_REDIS_URL) so they survive restarts; default: in memory")
	redisPrefix := fs.String("redis-prefix", coordinator.DefaultRedisPrefix, "`prefix` of every Redis key, so that farms can share a Redis")
	metricsListen := fs.String("metrics-listen", "", "serve Prometheus metrics over HTTP at `address`/metrics (HOST:PORT); default: off")
	cpuProfile := fs.String("cpu-profile", "", "write a Go CPU profile (go tool pprof) of the whole run to `file` when the coordinator stops (bench/cmd/loadsim)")
	if _, err := parse(fs, args, 0, 0); err != nil {
		return err
	}
	if *cpuProfile != "" {
		f, err := os.Create(*cpuProfile)
		if err != nil {
			return usageErrorf("coordinator: --cpu-profile: %v", err)
		}
		defer f.Close()
		if err := pprof.StartCPUProfile(f); err != nil {
			return fmt.Errorf("coordinator: --cpu-profile: %w", err)
		}
		defer pprof.StopCPUProfile()
	}
	clientTokens, err := loadTokens(*clientTokenFile, e.getenv("FARM_CLIENT_TOKENS"))
	if err != nil {
		return usageErrorf("coordinator: --client-token-file: %v", err)
	}
	workerTokens, err := loadTokens(*workerTokenFile, e.getenv("FARM_WORKER_TOKENS"))
	if err != nil {
		return usageErrorf("coordinator: --worker-token-file: %v", err)
	}
	var tlsConfig *tls.Config
	switch {
	case (*tlsCert == "") != (*tlsKey == ""):
		return usageErrorf("coordinator: --tls-cert and --tls-key go together")
	case *tlsCert != "":
		cert, err := tls.LoadX509KeyPair(*tlsCert, *tlsKey)
		if err != nil {
			return usageErrorf("coordinator: --tls-cert/--tls-key: %v", err)
		}
		tlsConfig = &tls.Config{Certificates: []tls.Certificate{cert}, MinVersion: tls.VersionTLS12}
	}
	var level slog.Level
	if err := level.UnmarshalText([]byte(*logLevel)); err != nil {
		return usageErrorf("coordinator: --log-level %q: want debug, info, warn or error", *logLevel)
	}
	if *dataDir == "" {
		return usageErrorf("coordinator: --data-dir must not be empty")
	}
	if *lease < 0 || *heartbeat < 0 || *stuck < 0 || *retain < 0 || *grace < 0 {
		return usageErrorf("coordinator: durations must not be negative")
	}
	if *redisURL == "" {
		*redisURL = e.getenv("FARM_REDIS_URL")
	}
	if *blobURL == "" {
		*blobURL = e.getenv("FARM_BLOB_URL")
	}
	logger := slog.New(slog.NewTextHandler(e.stderr, &slog.HandlerOptions{Level: level}))
	var metricsLis net.Listener
	if *metricsListen != "" {
		if metricsLis, err = net.Listen("tcp", *metricsListen); err != nil {
			return fmt.Errorf("coordinator: --metrics-listen: %w", err)
		}
		defer metricsLis.Close()
	}
	lis, err := net.Listen("tcp", *listen)
	if err != nil {
		return err
	}
	err = serveCoordinator(ctx, lis, coordinator.Config{
		DataDir:           *dataDir,
		BlobURL:           *blobURL,
		LeaseDuration:     *lease,
		HeartbeatInterval: *heartbeat,
		StuckTimeout:      *stuck,
		Retention:         *retain,
		BlobGrace:         *grace,
		Logger:            logger,
		ClientTokens:      clientTokens,
		WorkerTokens:      workerTokens,
		TLS:               tlsConfig,
		RedisURL:          *redisURL,
		RedisPrefix:       *redisPrefix,
	}, metricsLis, func(addr string) {
		warnAboutSecurity(e.stderr, logger, lis.Addr(), len(clientTokens), len(workerTokens), tlsConfig != nil)
		fmt.Fprintf(e.stderr, "coordinator listening on %s\n", addr)
		if metricsLis != nil {
			fmt.Fprintf(e.stderr, "metrics on http://%s/metrics\n", metricsLis.Addr())
		}
	})
	return err
}

// loadTokens reads the tokens of one role: those in file (one a line; blank lines and
// lines starting with # are skipped) and those in the comma-separated list fromEnv. A
// file given but holding no token is an error, so that a mistake cannot turn auth off.
func loadTokens(file, fromEnv string) ([]string, error) {
	var tokens []string
	for _, t := range strings.Split(fromEnv, ",") {
		if t = strings.TrimSpace(t); t != "" {
			tokens = append(tokens, t)
		}
	}
	if file == "" {
		return tokens, nil
	}
	data, err := os.ReadFile(file)
	if err != nil {
		return nil, err
	}
	n := 0
	for _, line := range strings.Split(string(data), "\n") {
		line = strings.TrimSpace(line)
		if line == "" || strings.HasPrefix(line, "#") {
			continue
		}
		tokens = append(tokens, line)
		n++
	}
	if n == 0 {
		return nil, fmt.Errorf("%s holds no token", file)
	}
	return tokens, nil
}

// warnAboutSecurity says what is unprotected: loudly, on stderr, if authentication is off
// on an address other machines can reach; in the log otherwise.
func warnAboutSecurity(w io.Writer, log *slog.Logger, addr net.Addr, clientTokens, workerTokens int, tlsOn bool) {
	loopback := isLoopbackAddr(addr)
	switch {
	case clientTokens == 0 && workerTokens == 0 && !loopback:
		fmt.Fprintf(w, `farm: WARNING: authentication is OFF and the coordinator listens on %s, reachable from other machines.
farm: WARNING: anyone who can connect may submit and cancel jobs, download every upload and image, and lease tasks.
farm: WARNING: give tokens with --client-token-file and --worker-token-file (and TLS with --tls-cert/--tls-key).
`, addr)
	case clientTokens == 0 && workerTokens == 0:
		log.Warn("authentication is off (no --client-token-file or --worker-token-file): any local process may use this coordinator")
	case clientTokens == 0:
		log.Warn("no client tokens: nobody can submit or follow jobs (--client-token-file)")
	case workerTokens == 0:
		log.Warn("no worker tokens: no worker can lease tasks (--worker-token-file)")
	}
	if (clientTokens > 0 || workerTokens > 0) && !tlsOn && !loopback {
		log.Warn("tokens travel in plaintext: anyone on the network path can read them; serve TLS with --tls-cert and --tls-key", "addr", addr.String())
	}
}

// isLoopbackAddr reports whether a listener's address accepts loopback connections only.
func isLoopbackAddr(a net.Addr) bool {
	tcp, ok := a.(*net.TCPAddr)
	return ok && tcp.IP.IsLoopback()
}

// serveCoordinator runs a coordinator on lis until ctx ends, calling ready once it is
// set up. It closes lis. A stop caused by ctx is not an error.
func serveCoordinator(ctx context.Context, lis net.Listener, cfg coordinator.Config, metricsLis net.Listener, ready func(addr string)) error {
	co, err := coordinator.New(cfg)
	if err != nil {
		lis.Close()
		return err
	}
	if metricsLis != nil {
		mux := http.NewServeMux()
		mux.Handle("/metrics", co.MetricsHandler())
		srv := &http.Server{Handler: mux, ReadHeaderTimeout: 10 * time.Second}
		go func() { _ = srv.Serve(metricsLis) }()
		defer srv.Close()
	}
	if ready != nil {
		ready(lis.Addr().String())
	}
	return co.Serve(ctx, lis)
}

// embeddedCoordinator is a coordinator served in-process on a loopback port.
type embeddedCoordinator struct {
	addr   string
	cancel context.CancelFunc
	done   chan error
}

// startEmbedded serves a coordinator on 127.0.0.1 with a free port, logging to logw, that
// accepts the given client and worker tokens.
func startEmbedded(dataDir string, lease time.Duration, logw io.Writer, clientToken, workerToken string) (*embeddedCoordinator, error) {
	lis, err := net.Listen("tcp", "127.0.0.1:0")
	if err != nil {
		return nil, err
	}
	ctx, cancel := context.WithCancel(context.Background())
	ec := &embeddedCoordinator{addr: lis.Addr().String(), cancel: cancel, done: make(chan error, 1)}
	ready := make(chan struct{})
	go func() {
		ec.done <- serveCoordinator(ctx, lis, coordinator.Config{
			DataDir:       dataDir,
			LeaseDuration: lease,
			Logger:        slog.New(slog.NewTextHandler(logw, &slog.HandlerOptions{Level: slog.LevelInfo})),
			ClientTokens:  []string{clientToken},
			WorkerTokens:  []string{workerToken},
		}, nil, func(string) { close(ready) })
	}()
	select {
	case <-ready:
		return ec, nil
	case err := <-ec.done:
		cancel()
		if err == nil {
			err = errors.New("coordinator stopped at once")
		}
		return nil, err
	}
}

// stop stops the coordinator gracefully, waiting at most timeout.
func (ec *embeddedCoordinator) stop(timeout time.Duration) error {
	ec.cancel()
	select {
	case err := <-ec.done:
		return err
	case <-time.After(timeout):
		return errors.New("coordinator did not stop within " + timeout.String())
	}
}
