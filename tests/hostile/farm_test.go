package hostile

import (
	"context"
	"path/filepath"
	"runtime"
	"strings"
	"testing"
	"time"

	"google.golang.org/grpc"
	"google.golang.org/grpc/codes"
	"google.golang.org/grpc/status"
	"google.golang.org/protobuf/proto"

	"photonfarm/client"
	"photonfarm/coordinator"
	"photonfarm/coordinator/coordinatortest"
	pb "photonfarm/proto/renderfarm/v1"
)

// repoRoot is the module root, two folders above this package.
func repoRoot() string {
	_, file, _, _ := runtime.Caller(0)
	return filepath.Dir(filepath.Dir(filepath.Dir(file)))
}

// farm is a coordinator serving on loopback, a client of it, and what is stored before
// the hostile requests: one job with a task leased by a registered worker, one cancelled
// job, and a second registered worker (the thief) that holds no lease.
type farm struct {
	ctx      context.Context
	c        *client.Client
	jobs     pb.JobServiceClient
	workers  pb.WorkerServiceClient // sends each registered worker's secret
	bare     pb.WorkerServiceClient // sends no worker secret
	blobs    pb.BlobServiceClient
	scene    *pb.Scene // valid, its mesh uploaded
	job      *pb.Job
	ended    *pb.Job
	workerID string
	lease    *pb.Lease
	thief    *pb.RegisterWorkerResponse
	srv      *coordinatortest.Server
}

func startFarm(t *testing.T) *farm {
	t.Helper()
	ctx, cancel := context.WithCancel(context.Background())
	t.Cleanup(cancel)
	f := &farm{ctx: ctx, srv: coordinatortest.Serve(t, coordinator.Config{LeaseDuration: time.Minute})}
	var err error
	if f.c, err = client.Dial(f.srv.Addr); err != nil {
		t.Fatal(err)
	}
	t.Cleanup(func() { f.c.Close() })
	conn := f.srv.Dial(t, client.WorkerSecrets(), grpc.WithDefaultCallOptions(grpc.MaxCallRecvMsgSize(128<<20), grpc.MaxCallSendMsgSize(128<<20)))
	f.jobs, f.workers, f.blobs = pb.NewJobServiceClient(conn), pb.NewWorkerServiceClient(conn), pb.NewBlobServiceClient(conn)
	f.bare = pb.NewWorkerServiceClient(f.srv.Dial(t))

	sc, err := f.c.LoadSceneFile(ctx, filepath.Join(repoRoot(), "scenes", "test-small.json"))
	if err != nil {
		t.Fatal(err)
	}
	f.scene = sc
	if f.job, err = f.c.Submit(ctx, sc); err != nil {
		t.Fatal(err)
	}
	if f.ended, err = f.c.Submit(ctx, sc); err != nil {
		t.Fatal(err)
	}
	if f.ended, err = f.c.Cancel(ctx, f.ended.GetId()); err != nil {
		t.Fatal(err)
	}
	reg, err := f.workers.RegisterWorker(ctx, &pb.RegisterWorkerRequest{Hostname: "honest", Cores: 1})
	if err != nil {
		t.Fatal(err)
	}
	f.workerID = reg.GetWorkerId()
	l, err := f.workers.LeaseTask(ctx, &pb.LeaseTaskRequest{WorkerId: f.workerID})
	if err != nil || l.GetLease() == nil {
		t.Fatalf("lease: %v, %v", l, err)
	}
	f.lease = l.GetLease()
	if f.thief, err = f.workers.RegisterWorker(ctx, &pb.RegisterWorkerRequest{Hostname: "thief", Cores: 1}); err != nil {
		t.Fatal(err)
	}
	return f
}

// state is every stored job and task, for comparing before and after.
func (f *farm) state(t *testing.T) []proto.Message {
	t.Helper()
	jobs, err := f.c.ListJobs(f.ctx)
	if err != nil {
		t.Fatalf("ListJobs: %v (is the coordinator still up?)", err)
	}
	var out []proto.Message
	for _, j := range jobs {
		out = append(out, j)
		tasks, err := f.c.ListTasks(f.ctx, j.GetId())
		if err != nil {
			t.Fatal(err)
		}
		for _, task := range tasks {
			out = append(out, task)
		}
	}
	return out
}

// hostileCase is one request and what it must get back.
type hostileCase struct {
	name string
	call func(ctx context.Context) error
	code codes.Code
	// want is a substring of the status message: the field or the reason.
	want string
}

func check(t *testing.T, f *farm, c hostileCase) {
	t.Helper()
	err := c.call(f.ctx)
	st, _ := status.FromError(err)
	if st.Code() != c.code || !strings.Contains(st.Message(), c.want) {
		t.Errorf("got %v %q, want %v with %q", st.Code(), st.Message(), c.code, c.want)
	}
	if c.code != codes.OK && strings.TrimSpace(st.Message()) == "" {
		t.Error("a refusal without a message")
	}
}
