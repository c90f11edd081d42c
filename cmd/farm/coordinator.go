package main

import (
	"context"
	"errors"
	"fmt"
	"io"
	"log/slog"
	"net"
	"os"
	"path/filepath"
	"time"

	"photonfarm/coordinator"
)

var coordinatorVerb = &verb{
	name:    "coordinator",
	args:    "[--listen ADDR] [--data-dir DIR] [--lease-duration D]",
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
	lease := fs.Duration("lease-duration", coordinator.DefaultLeaseDuration, "how long a task lease lasts without a heartbeat")
	heartbeat := fs.Duration("heartbeat-interval", 0, "how often workers heartbeat (0: a quarter of the lease duration)")
	logLevel := fs.String("log-level", "info", "log level: debug, info, warn, error")
	if _, err := parse(fs, args, 0, 0); err != nil {
		return err
	}
	var level slog.Level
	if err := level.UnmarshalText([]byte(*logLevel)); err != nil {
		return usageErrorf("coordinator: --log-level %q: want debug, info, warn or error", *logLevel)
	}
	if *dataDir == "" {
		return usageErrorf("coordinator: --data-dir must not be empty")
	}
	if *lease < 0 || *heartbeat < 0 {
		return usageErrorf("coordinator: durations must not be negative")
	}
	logger := slog.New(slog.NewTextHandler(e.stderr, &slog.HandlerOptions{Level: level}))
	lis, err := net.Listen("tcp", *listen)
	if err != nil {
		return err
	}
	err = serveCoordinator(ctx, lis, coordinator.Config{
		DataDir:           *dataDir,
		LeaseDuration:     *lease,
		HeartbeatInterval: *heartbeat,
		Logger:            logger,
	}, func(addr string) { fmt.Fprintf(e.stderr, "coordinator listening on %s\n", addr) })
	return err
}

// serveCoordinator runs a coordinator on lis until ctx ends, calling ready once it is
// set up. It closes lis. A stop caused by ctx is not an error.
func serveCoordinator(ctx context.Context, lis net.Listener, cfg coordinator.Config, ready func(addr string)) error {
	co, err := coordinator.New(cfg)
	if err != nil {
		lis.Close()
		return err
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

// startEmbedded serves a coordinator on 127.0.0.1 with a free port, logging to logw.
func startEmbedded(dataDir string, lease time.Duration, logw io.Writer) (*embeddedCoordinator, error) {
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
		}, func(string) { close(ready) })
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
