package farmtest

import (
	"context"
	"net"
	"testing"
	"time"

	"google.golang.org/grpc"
	"google.golang.org/grpc/credentials/insecure"

	"photonfarm/client"
	pb "photonfarm/proto/renderfarm/v1"
)

// FailNextTask plays a worker that says what kind of failure it had (as farm-worker does
// for a broken mesh): it registers, with workerToken when the farm has tokens, leases the
// next task, fails it with reason as kind, and unregisters. It returns the task's id.
func (f *Farm) FailNextTask(t testing.TB, workerToken string, kind pb.FailureKind, reason string) string {
	t.Helper()
	conn, err := grpc.NewClient(f.Addr, grpc.WithTransportCredentials(insecure.NewCredentials()), client.WorkerSecrets())
	if err != nil {
		t.Fatal(err)
	}
	defer conn.Close()
	ctx, cancel := context.WithTimeout(context.Background(), 30*time.Second)
	defer cancel()
	ctx = client.ContextWithToken(ctx, workerToken)
	w := pb.NewWorkerServiceClient(conn)
	reg, err := w.RegisterWorker(ctx, &pb.RegisterWorkerRequest{Hostname: "farmtest-failing-worker"})
	if err != nil {
		t.Fatal(err)
	}
	l, err := w.LeaseTask(ctx, &pb.LeaseTaskRequest{WorkerId: reg.GetWorkerId()})
	if err != nil || l.GetLease() == nil {
		t.Fatalf("LeaseTask = %v, %v; want a task", l, err)
	}
	if _, err := w.FailTask(ctx, &pb.FailTaskRequest{WorkerId: reg.GetWorkerId(), TaskId: l.GetLease().GetTaskId(),
		Epoch: l.GetLease().GetEpoch(), Error: reason, Kind: kind}); err != nil {
		t.Fatal(err)
	}
	if _, err := w.UnregisterWorker(ctx, &pb.UnregisterWorkerRequest{WorkerId: reg.GetWorkerId()}); err != nil {
		t.Fatal(err)
	}
	return l.GetLease().GetTaskId()
}

// ClosedAddress is a loopback address where nothing listens.
func ClosedAddress(t testing.TB) string {
	t.Helper()
	lis, err := net.Listen("tcp", "127.0.0.1:0")
	if err != nil {
		t.Fatal(err)
	}
	addr := lis.Addr().String()
	lis.Close()
	return addr
}
