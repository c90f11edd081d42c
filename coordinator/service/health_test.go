package service_test

import (
	"context"
	"testing"
	"time"

	"google.golang.org/grpc/codes"
	healthpb "google.golang.org/grpc/health/grpc_health_v1"
	"google.golang.org/grpc/status"

	"photonfarm/coordinator/service"
	"photonfarm/coordinator/store"
	"photonfarm/coordinator/store/redisstore"
	"photonfarm/coordinator/store/redisstore/redistest"
)

// Kubernetes' grpc liveness and readiness probes (deploy/k8s) ask the server as a whole
// (service ""); an unknown service name must not pass for healthy.
func TestHealthServiceAnswersForTheServer(t *testing.T) {
	f := newFarm(t)
	resp, err := f.health.Check(f.ctx, &healthpb.HealthCheckRequest{})
	if err != nil {
		t.Fatalf("Check: %v", err)
	}
	if resp.GetStatus() != healthpb.HealthCheckResponse_SERVING {
		t.Fatalf("status = %v, want SERVING", resp.GetStatus())
	}
	_, err = f.health.Check(f.ctx, &healthpb.HealthCheckRequest{Service: "no.such.Service"})
	if status.Code(err) != codes.NotFound {
		t.Fatalf("Check of an unknown service: %v, want NotFound", err)
	}
}

// A coordinator cut off from Redis must say so, so that a readiness probe stops sending it
// work, and say SERVING again once Redis is back (a real redis-server, killed and started).
func TestHealthFollowsRedis(t *testing.T) {
	srv := redistest.Start(t)
	f := newFarmOn(t, func(opts store.Options) store.Store {
		st, err := redisstore.New(context.Background(), srv.Client(), "health", opts)
		if err != nil {
			t.Fatal(err)
		}
		return st
	})
	waitHealth(t, f, healthpb.HealthCheckResponse_SERVING)
	srv.Kill()
	waitHealth(t, f, healthpb.HealthCheckResponse_NOT_SERVING)
	srv.Revive()
	waitHealth(t, f, healthpb.HealthCheckResponse_SERVING)
}

// waitHealth polls the server's health until it is want, failing after a few of the
// service's check intervals.
func waitHealth(t *testing.T, f *farm, want healthpb.HealthCheckResponse_ServingStatus) {
	t.Helper()
	deadline := time.Now().Add(5*service.HealthInterval + service.HealthTimeout)
	var last healthpb.HealthCheckResponse_ServingStatus
	for time.Now().Before(deadline) {
		resp, err := f.health.Check(f.ctx, &healthpb.HealthCheckRequest{})
		if err != nil {
			t.Fatalf("Check: %v", err)
		}
		if last = resp.GetStatus(); last == want {
			return
		}
		time.Sleep(50 * time.Millisecond)
	}
	t.Fatalf("health = %v, want %v", last, want)
}
