package service

import (
	"context"
	"time"

	"google.golang.org/grpc/health"
	healthpb "google.golang.org/grpc/health/grpc_health_v1"
)

// HealthInterval is how often the health service asks the store and the blob store
// whether they answer; HealthTimeout bounds each question.
const (
	HealthInterval = time.Second
	HealthTimeout  = 2 * time.Second
)

// pinger is a dependency that can say whether it answers (the Redis store, the blob
// store). The in-memory store has no Ping: it cannot be unreachable.
type pinger interface {
	Ping(ctx context.Context) error
}

// watchHealth keeps the health service's answer for the server ("") honest: NOT_SERVING
// while the store or the blob store does not answer, SERVING again once both do, so a
// readiness probe takes a coordinator cut off from Redis out of rotation. It runs until
// Shutdown.
func (s *Service) watchHealth(h *health.Server) {
	deps := []struct {
		name string
		dep  any
	}{{"store", s.cfg.Store}, {"blob store", s.cfg.Blobs}}
	last := healthpb.HealthCheckResponse_UNKNOWN
	check := func() {
		st := healthpb.HealthCheckResponse_SERVING
		for _, d := range deps {
			p, ok := d.dep.(pinger)
			if !ok {
				continue
			}
			ctx, cancel := context.WithTimeout(context.Background(), HealthTimeout)
			err := p.Ping(ctx)
			cancel()
			if err != nil {
				if last != healthpb.HealthCheckResponse_NOT_SERVING {
					s.log.Warn("health: not serving", "dependency", d.name, "err", err)
				}
				st = healthpb.HealthCheckResponse_NOT_SERVING
				break
			}
		}
		if st != last && st == healthpb.HealthCheckResponse_SERVING && last != healthpb.HealthCheckResponse_UNKNOWN {
			s.log.Info("health: serving again")
		}
		last = st
		h.SetServingStatus("", st)
	}
	check()
	t := time.NewTicker(HealthInterval)
	defer t.Stop()
	for {
		select {
		case <-s.done:
			h.Shutdown()
			return
		case <-t.C:
			check()
		}
	}
}
