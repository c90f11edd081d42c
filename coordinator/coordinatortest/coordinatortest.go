// Package coordinatortest runs a real coordinator in the test's process, on a loopback
// port, for the tests that talk gRPC to it (the coordinator's own, the hostile suite, the
// dashboard's, the CLI's).
package coordinatortest

import (
	"context"
	"errors"
	"net"
	"testing"
	"time"

	"google.golang.org/grpc"
	"google.golang.org/grpc/credentials/insecure"

	"photonfarm/coordinator"
)

// stopTimeout bounds how long a stopping coordinator may take to return from Serve.
const stopTimeout = 5 * time.Second

// Server is a coordinator serving on a loopback port.
type Server struct {
	// Addr is where it listens: "127.0.0.1:PORT".
	Addr string
	// Coordinator is what serves there (for its MetricsHandler).
	Coordinator *coordinator.Coordinator
	cancel      context.CancelFunc
	done        chan struct{}
	err         error
}

// Serve runs cfg's coordinator (in a temporary folder when cfg names no DataDir) on a
// loopback port until Stop or the end of the test. A Serve that fails, or that does not
// return within 5 s of being stopped, fails the test.
func Serve(t testing.TB, cfg coordinator.Config) *Server {
	t.Helper()
	if cfg.DataDir == "" {
		cfg.DataDir = t.TempDir()
	}
	c, err := coordinator.New(cfg)
	if err != nil {
		t.Fatal(err)
	}
	lis, err := net.Listen("tcp", "127.0.0.1:0")
	if err != nil {
		t.Fatal(err)
	}
	ctx, cancel := context.WithCancel(context.Background())
	s := &Server{Addr: lis.Addr().String(), Coordinator: c, cancel: cancel, done: make(chan struct{})}
	go func() {
		s.err = c.Serve(ctx, lis)
		close(s.done)
	}()
	t.Cleanup(func() {
		if err := s.Stop(); err != nil {
			t.Errorf("coordinator Serve: %v", err)
		}
	})
	return s
}

// Stop cancels Serve and returns what it returned (nil for a graceful stop), or an error
// if it has not returned within 5 s. Stopping again returns the same.
func (s *Server) Stop() error {
	s.cancel()
	select {
	case <-s.done:
		return s.err
	case <-time.After(stopTimeout):
		return errors.New("Serve did not return within " + stopTimeout.String() + " of being stopped")
	}
}

// Done is closed once Serve has returned; Err then says why.
func (s *Server) Done() <-chan struct{} { return s.done }

// Err is what Serve returned, once Done is closed.
func (s *Server) Err() error { return s.err }

// Dial returns a plaintext gRPC connection to the coordinator, without credentials of its
// own (calls carry their token in their context, if any), closed when the test ends.
func (s *Server) Dial(t testing.TB, opts ...grpc.DialOption) *grpc.ClientConn {
	t.Helper()
	conn, err := grpc.NewClient(s.Addr, append(opts, grpc.WithTransportCredentials(insecure.NewCredentials()))...)
	if err != nil {
		t.Fatal(err)
	}
	t.Cleanup(func() { conn.Close() })
	return conn
}

// Call returns a call of the unary method m (a method value of a gRPC client) with req that
// keeps only the error: a row of a table of requests that must be refused.
func Call[Req, Resp any](m func(context.Context, Req, ...grpc.CallOption) (Resp, error), req Req) func(context.Context) error {
	return func(ctx context.Context) error {
		_, err := m(ctx, req)
		return err
	}
}
