package coordinator_test

import (
	"context"
	"log/slog"
	"net"
	"testing"
	"time"

	"google.golang.org/grpc"
	"google.golang.org/grpc/credentials/insecure"
	"google.golang.org/protobuf/types/known/durationpb"

	"photonfarm/contract/scene/scenetest"
	"photonfarm/coordinator"
	pb "photonfarm/proto/renderfarm/v1"
)

// listenAndServe runs cfg's coordinator (in a temporary data folder, logging nowhere) on
// a loopback port and returns its address and a stop function that cancels Serve and
// returns Serve's result (failing the test if Serve has not returned within 5 s).
func listenAndServe(t *testing.T, cfg coordinator.Config) (string, func() error) {
	t.Helper()
	cfg.DataDir = t.TempDir()
	cfg.Logger = slog.New(slog.DiscardHandler)
	c, err := coordinator.New(cfg)
	if err != nil {
		t.Fatal(err)
	}
	lis, err := net.Listen("tcp", "127.0.0.1:0")
	if err != nil {
		t.Fatal(err)
	}
	ctx, cancel := context.WithCancel(context.Background())
	served := make(chan error, 1)
	go func() { served <- c.Serve(ctx, lis) }()
	stop := func() error {
		cancel()
		select {
		case err := <-served:
			return err
		case <-time.After(5 * time.Second):
			t.Fatal("Serve did not stop within 5s")
			return nil
		}
	}
	return lis.Addr().String(), stop
}

// startServing runs a coordinator with the given lease duration and returns a
// connection to it (closed when the test ends) and listenAndServe's stop function.
func startServing(t *testing.T, lease time.Duration) (*grpc.ClientConn, func() error) {
	t.Helper()
	addr, stop := listenAndServe(t, coordinator.Config{LeaseDuration: lease})
	conn, err := grpc.NewClient(addr, grpc.WithTransportCredentials(insecure.NewCredentials()))
	if err != nil {
		stop()
		t.Fatal(err)
	}
	t.Cleanup(func() { conn.Close() })
	return conn, stop
}

func TestNewRejectsBadConfig(t *testing.T) {
	for _, cfg := range []coordinator.Config{
		{},
		{DataDir: t.TempDir(), LeaseDuration: time.Second, HeartbeatInterval: 2 * time.Second},
		{DataDir: t.TempDir(), LeaseDuration: -time.Second},
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
