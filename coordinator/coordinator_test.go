package coordinator_test

import (
	"context"
	"log/slog"
	"testing"
	"time"

	"google.golang.org/grpc"
	"google.golang.org/protobuf/types/known/durationpb"

	"photonfarm/client"
	"photonfarm/contract/scene/scenetest"
	"photonfarm/coordinator"
	"photonfarm/coordinator/coordinatortest"
	pb "photonfarm/proto/renderfarm/v1"
)

// serve runs cfg's coordinator, logging nowhere, on a loopback port until the test ends.
func serve(t *testing.T, cfg coordinator.Config) *coordinatortest.Server {
	t.Helper()
	cfg.Logger = slog.New(slog.DiscardHandler)
	return coordinatortest.Serve(t, cfg)
}

// startServing runs a coordinator with the given lease duration and returns a
// connection to it (closed when the test ends) and the function that stops it early.
func startServing(t *testing.T, lease time.Duration) (*grpc.ClientConn, func() error) {
	t.Helper()
	s := serve(t, coordinator.Config{LeaseDuration: lease})
	return s.Dial(t, client.WorkerSecrets()), s.Stop
}

func TestNewRejectsBadConfig(t *testing.T) {
	for _, cfg := range []coordinator.Config{
		{},
		{DataDir: t.TempDir(), LeaseDuration: time.Second, HeartbeatInterval: 2 * time.Second},
		{DataDir: t.TempDir(), LeaseDuration: -time.Second},
		{DataDir: t.TempDir(), BlobURL: "ftp://farm"},
		{DataDir: t.TempDir(), BlobURL: "s3://AKIA:hunter2@farm?endpoint=http://127.0.0.1:1"},
	} {
		if _, err := coordinator.New(cfg); err == nil {
			t.Errorf("New(%+v) succeeded", cfg)
		}
	}
}

// TestServeExpiresLeasesAndStopsGracefully runs the real thing: a lease that is never
// extended goes back to the queue, and cancelling the context stops Serve promptly even
// with a worker long-polling.
func TestServeExpiresLeasesAndStopsGracefully(t *testing.T) {
	conn, stop := startServing(t, 200*time.Millisecond)
	rpc, cancel := context.WithTimeout(context.Background(), 20*time.Second)
	defer cancel()
	jobs, workers := pb.NewJobServiceClient(conn), pb.NewWorkerServiceClient(conn)
	if _, err := jobs.SubmitJob(rpc, &pb.SubmitJobRequest{Scene: scenetest.Unlit(8, 8)}); err != nil {
		t.Fatal(err)
	}
	reg, err := workers.RegisterWorker(rpc, &pb.RegisterWorkerRequest{Hostname: "t"})
	if err != nil {
		t.Fatal(err)
	}
	if reg.HeartbeatInterval.AsDuration() != 50*time.Millisecond {
		t.Errorf("heartbeat interval = %v, want LeaseDuration/4", reg.HeartbeatInterval.AsDuration())
	}
	first, err := workers.LeaseTask(rpc, &pb.LeaseTaskRequest{WorkerId: reg.WorkerId})
	if err != nil || first.Lease == nil {
		t.Fatalf("LeaseTask = %v, %v", first, err)
	}
	// No heartbeat: the sweeper requeues the task and a long poll gets it back.
	again, err := workers.LeaseTask(rpc, &pb.LeaseTaskRequest{WorkerId: reg.WorkerId, WaitTimeout: durationpb.New(5 * time.Second)})
	if err != nil || again.Lease.GetTaskId() != first.Lease.TaskId || again.Lease.Epoch <= first.Lease.Epoch {
		t.Fatalf("after expiry LeaseTask = %v, %v", again, err)
	}

	polled := make(chan error, 1)
	go func() {
		_, err := workers.LeaseTask(rpc, &pb.LeaseTaskRequest{WorkerId: reg.WorkerId, WaitTimeout: durationpb.New(30 * time.Second)})
		polled <- err
	}()
	time.Sleep(100 * time.Millisecond)
	start := time.Now()
	if err := stop(); err != nil {
		t.Errorf("Serve = %v", err)
	}
	if d := time.Since(start); d > 3*time.Second {
		t.Errorf("stopping took %v", d)
	}
	if err := <-polled; err != nil {
		t.Errorf("long poll during shutdown: %v, want an empty response", err)
	}
}
