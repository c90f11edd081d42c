package metrics

import (
	"context"
	"time"

	"google.golang.org/grpc"
	"google.golang.org/grpc/codes"
	"google.golang.org/grpc/status"
)

// UnaryServerInterceptor times unary calls by method and status code. Install it first
// in the chain so that it sees the status the error mapping produced.
func (m *Metrics) UnaryServerInterceptor(ctx context.Context, req any, info *grpc.UnaryServerInfo, h grpc.UnaryHandler) (any, error) {
	start := time.Now()
	resp, err := h(ctx, req)
	m.observe(info.FullMethod, start, err)
	return resp, err
}

// StreamServerInterceptor times streaming calls (WatchJob, blob transfers) to their end.
func (m *Metrics) StreamServerInterceptor(srv any, ss grpc.ServerStream, info *grpc.StreamServerInfo, h grpc.StreamHandler) error {
	start := time.Now()
	err := h(srv, ss)
	m.observe(info.FullMethod, start, err)
	return err
}

func (m *Metrics) observe(method string, start time.Time, err error) {
	m.rpcSeconds.WithLabelValues(method, status.Code(err).String()).Observe(time.Since(start).Seconds())
}

// CallRefused counts a call the token check refused before its stream was created, which
// no interceptor sees. method must come from a bounded set (auth.MethodLabel).
func (m *Metrics) CallRefused(method string, code codes.Code) {
	if m != nil {
		m.rpcRefused.WithLabelValues(method, code.String()).Inc()
	}
}
