package service_test

import (
	"testing"

	"google.golang.org/grpc/codes"
	healthpb "google.golang.org/grpc/health/grpc_health_v1"
	"google.golang.org/grpc/status"
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
