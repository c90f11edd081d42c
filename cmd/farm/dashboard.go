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
	"time"

	"google.golang.org/grpc"
	"google.golang.org/grpc/credentials"
	"google.golang.org/grpc/credentials/insecure"

	"photonfarm/client"
	"photonfarm/services/dashboard"
)

var dashboardVerb = &verb{
	name:    "dashboard",
	args:    "[--coordinator ADDR] [--listen 127.0.0.1:8080] [--tls-ca F] [--insecure]",
	summary: "serve the web dashboard of a coordinator",
	run:     runDashboard,
}

// dashboardStopTimeout bounds a graceful stop of the dashboard's HTTP server.
const dashboardStopTimeout = 5 * time.Second

func runDashboard(ctx context.Context, e *env, args []string) error {
	fs := newFlags("dashboard", e)
	addr := coordinatorFlag(fs, e)
	listen := fs.String("listen", "127.0.0.1:8080", "HTTP `address` to serve the dashboard on, HOST:PORT (port 0 picks a free one)")
	tlsCA := fs.String("tls-ca", "", "reach the coordinator over TLS, trusting the CA certificates in this PEM `file` (default $FARM_TLS_CA; none: plaintext)")
	insecureFlag := fs.Bool("insecure", false, "allow forwarding browsers' tokens without TLS to a coordinator that is not on loopback")
	if _, err := parse(fs, args, 0, 0); err != nil {
		return err
	}
	ca := *tlsCA
	if ca == "" {
		ca = e.getenv("FARM_TLS_CA")
	}
	coord := addr()
	if ca == "" && !*insecureFlag && !client.IsLoopback(coord) {
		return usageErrorf("dashboard: refusing to forward tokens without TLS to %s, which is not loopback: pass --tls-ca FILE, or --insecure on a trusted network", coord)
	}
	conn, err := dialForDashboard(coord, ca)
	if err != nil {
		return err
	}
	defer conn.Close()
	lis, err := net.Listen("tcp", *listen)
	if err != nil {
		return fmt.Errorf("dashboard: --listen: %w", err)
	}
	if !isLoopbackAddr(lis.Addr()) {
		fmt.Fprintf(e.stderr, "farm: WARNING: the dashboard serves plain HTTP on %s: browsers' tokens cross the network unencrypted; put it behind a TLS proxy or listen on loopback\n", lis.Addr())
	}
	logger := slog.New(slog.NewTextHandler(e.stderr, &slog.HandlerOptions{Level: slog.LevelInfo}))
	return serveDashboard(ctx, lis, conn, logger, func(url string) {
		fmt.Fprintf(e.stdout, "dashboard on %s\n", url)
	})
}

// dialForDashboard connects to the coordinator without per-RPC credentials (the
// dashboard forwards each browser's token), over TLS trusting caFile if it is set.
func dialForDashboard(addr, caFile string) (*grpc.ClientConn, error) {
	creds := insecure.NewCredentials()
	if caFile != "" {
		pool, err := client.LoadCertPool(caFile)
		if err != nil {
			return nil, usageErrorf("dashboard: --tls-ca: %v", err)
		}
		creds = credentials.NewTLS(&tls.Config{MinVersion: tls.VersionTLS12, RootCAs: pool})
	}
	target, targetOpts, err := client.ReplicaTarget(addr)
	if err != nil {
		return nil, usageErrorf("dashboard: %v", err)
	}
	conn, err := grpc.NewClient(target, append(append(dashboard.DialOptions(), targetOpts...), grpc.WithTransportCredentials(creds))...)
	if err != nil {
		return nil, fmt.Errorf("dashboard: coordinator address %q: %w", addr, err)
	}
	return conn, nil
}

// serveDashboard serves the dashboard for the coordinator behind conn on lis until ctx
// ends, calling ready with its URL once it accepts connections. It closes lis. Requests
// under way (event streams) end with ctx.
func serveDashboard(ctx context.Context, lis net.Listener, conn grpc.ClientConnInterface, logger *slog.Logger, ready func(url string)) error {
	srv := &http.Server{
		Handler:           dashboard.New(dashboard.Config{Conn: conn, Logger: logger}),
		ReadHeaderTimeout: 10 * time.Second,
		// Headers carry a token of at most 4096 bytes; a browser's others are small.
		MaxHeaderBytes: 64 << 10,
		IdleTimeout:    2 * time.Minute,
		BaseContext:    func(net.Listener) context.Context { return ctx },
		ErrorLog:       slog.NewLogLogger(logger.Handler(), slog.LevelWarn),
	}
	done := make(chan error, 1)
	go func() { done <- srv.Serve(lis) }()
	if ready != nil {
		ready("http://" + lis.Addr().String() + "/")
	}
	select {
	case err := <-done:
		return err
	case <-ctx.Done():
	}
	sctx, cancel := context.WithTimeout(context.Background(), dashboardStopTimeout)
	defer cancel()
	if err := srv.Shutdown(sctx); err != nil {
		srv.Close()
	}
	if err := <-done; !errors.Is(err, http.ErrServerClosed) {
		return err
	}
	return nil
}

// embeddedDashboard is a dashboard served in-process next to farm render's coordinator.
type embeddedDashboard struct {
	url    string
	conn   *grpc.ClientConn
	cancel context.CancelFunc
	done   chan error
}

// startEmbeddedDashboard serves a dashboard for the coordinator at coordAddr (loopback,
// plaintext) on listen, logging to logw.
func startEmbeddedDashboard(coordAddr, listen string, logw io.Writer) (*embeddedDashboard, error) {
	conn, err := dialForDashboard(coordAddr, "")
	if err != nil {
		return nil, err
	}
	lis, err := net.Listen("tcp", listen)
	if err != nil {
		conn.Close()
		return nil, fmt.Errorf("--dashboard-listen: %w", err)
	}
	ctx, cancel := context.WithCancel(context.Background())
	d := &embeddedDashboard{conn: conn, cancel: cancel, done: make(chan error, 1)}
	ready := make(chan string, 1)
	logger := slog.New(slog.NewTextHandler(logw, &slog.HandlerOptions{Level: slog.LevelInfo}))
	go func() { d.done <- serveDashboard(ctx, lis, conn, logger, func(url string) { ready <- url }) }()
	d.url = <-ready
	return d, nil
}

// stop stops the dashboard and closes its connection to the coordinator.
func (d *embeddedDashboard) stop() error {
	d.cancel()
	err := <-d.done
	d.conn.Close()
	return err
}
