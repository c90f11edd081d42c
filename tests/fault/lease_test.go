package fault

import (
	"context"
	"flag"
	"slices"
	"sync"
	"testing"
	"time"

	"google.golang.org/grpc"
	"google.golang.org/grpc/credentials/insecure"
	"google.golang.org/protobuf/types/known/durationpb"

	"photonfarm/client"
	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

var (
	leaseWorkers = flag.Int("lease-workers", 8, "fake workers of the lease throughput test, each with its own connection")
	leaseTiles   = flag.Int("lease-tiles", 4096, "render tiles of the lease throughput test's job (rounded up to a multiple of 64)")
)

// TestLeaseThroughputOnRedis measures the lease path through gRPC and Redis: -lease-workers
// fake workers, each with a connection of its own, register with a coordinator on Redis
// and lease and complete the tasks of one job of -lease-tiles tiles as fast as they can,
// completing each with a tiny uploaded blob. It prints leases per second and the p50 and
// p99 latencies of LeaseTask and CompleteTask; it asserts only correctness (the machines
// are shared, so speed is not asserted): every task was completed once, on its first lease,
// and the job succeeded.
func TestLeaseThroughputOnRedis(t *testing.T) {
	// Leases of a minute: the fake workers do not heartbeat.
	f := startRedisFarm(t, "--lease-duration", "1m")
	ctx, cancel := context.WithTimeout(context.Background(), 5*time.Minute)
	defer cancel()
	blob := []byte("not really an EXR")
	digest, err := f.Client.UploadBytes(ctx, blob)
	if err != nil {
		t.Fatal(err)
	}
	output := &pb.Artifact{Digest: digest, SizeBytes: int64(len(blob))}

	sc := tinyScene(t, f, 1)
	rows := (*leaseTiles + 63) / 64
	sc.Film = &pb.Film{Width: 64 * 8, Height: uint32(rows) * 8, TileSize: 8}
	job := f.Submit(t, sc)
	// ended tells the fake workers to stop once nothing is left to lease; if the watch
	// breaks early, tasks are left and the checks below say so.
	ended := make(chan struct{})
	go func() {
		defer close(ended)
		f.Client.Watch(ctx, job.GetId(), nil)
	}()

	var (
		mu        sync.Mutex
		completed = map[string]int{}
		leaseLat  []time.Duration
		doneLat   []time.Duration
		wg        sync.WaitGroup
	)
	start := time.Now()
	for w := range *leaseWorkers {
		wg.Add(1)
		go func() {
			defer wg.Done()
			lw := fakeWorker(t, f.Addr, w)
			defer lw.close()
			cl := lw.run(t, ctx, ended, func(resp *pb.LeaseTaskResponse) []*pb.Artifact {
				if resp.GetTask().GetComposite() != nil {
					return named(output, "image.exr", "preview.png")
				}
				return named(output, "tile.exr")
			})
			mu.Lock()
			defer mu.Unlock()
			leaseLat = append(leaseLat, cl.leases...)
			doneLat = append(doneLat, cl.completes...)
			for _, id := range cl.tasks {
				completed[id]++
			}
		}()
	}
	wg.Wait()
	elapsed := time.Since(start)

	done := f.Wait(t, job.GetId(), 10*time.Second)
	tasks := f.Tasks(t, done.GetId())
	for _, task := range tasks {
		if n := completed[task.GetId()]; n != 1 || task.GetState() != pb.TaskState_TASK_STATE_SUCCEEDED || task.GetAttempts() != 1 {
			t.Errorf("task %s: completed %d times, %v after %d leases; want once, succeeded, 1 lease", task.GetId(), n, task.GetState(), task.GetAttempts())
		}
	}
	if len(completed) != len(tasks) {
		t.Errorf("%d tasks completed, the job has %d", len(completed), len(tasks))
	}
	t.Logf("%d fake workers, %d tasks (%d tiles + composite) on Redis: %.0f leases/s (lease+complete round trips, %s in all)",
		*leaseWorkers, len(tasks), len(farmtest.TasksOf(tasks, pb.Phase_PHASE_RENDER)), float64(len(leaseLat))/elapsed.Seconds(), elapsed.Round(time.Millisecond))
	t.Logf("LeaseTask latency: p50 %s, p99 %s, max %s", pct(leaseLat, 50), pct(leaseLat, 99), pct(leaseLat, 100))
	t.Logf("CompleteTask latency: p50 %s, p99 %s, max %s", pct(doneLat, 50), pct(doneLat, 99), pct(doneLat, 100))
}

// completedLog is what one fake worker measured and completed.
type completedLog struct {
	leases, completes []time.Duration // latencies of LeaseTask calls that got a task, and of CompleteTask
	phases            []pb.Phase      // of each of those leases' task
	tasks             []string        // the tasks it completed
}

// pct is the p-th percentile (nearest rank) of ds, 0 if ds is empty.
func pct(ds []time.Duration, p int) time.Duration {
	if len(ds) == 0 {
		return 0
	}
	s := slices.Clone(ds)
	slices.Sort(s)
	i := max((len(s)*p+99)/100-1, 0)
	return s[i].Round(10 * time.Microsecond)
}

// leaseWorker is a fake worker: a connection and a registered worker id.
type leaseWorker struct {
	conn *grpc.ClientConn
	ws   pb.WorkerServiceClient
	id   string
}

// fakeWorker connects to addr and registers as worker number n; on a failure it reports
// with t.Errorf (it runs on a goroutine of its own) and returns a worker whose run does
// nothing.
func fakeWorker(t *testing.T, addr string, n int) *leaseWorker {
	conn, err := grpc.NewClient(addr, grpc.WithTransportCredentials(insecure.NewCredentials()), client.WorkerSecrets(),
		grpc.WithDefaultCallOptions(grpc.MaxCallRecvMsgSize(int(rules.RPC.GetMaxMessageBytes())))) // a composite of 65,536 tiles is 6.6 MB
	if err != nil {
		t.Errorf("fake worker %d: %v", n, err)
		return &leaseWorker{}
	}
	lw := &leaseWorker{conn: conn, ws: pb.NewWorkerServiceClient(conn)}
	resp, err := lw.ws.RegisterWorker(context.Background(), &pb.RegisterWorkerRequest{Hostname: "fake", Cores: 1, Version: "lease-test"})
	if err != nil {
		t.Errorf("fake worker %d: register: %v", n, err)
		return lw
	}
	lw.id = resp.GetWorkerId()
	return lw
}

func (lw *leaseWorker) close() {
	if lw.conn != nil {
		lw.conn.Close()
	}
}

// named is output under each of names.
func named(output *pb.Artifact, names ...string) []*pb.Artifact {
	var out []*pb.Artifact
	for _, n := range names {
		out = append(out, &pb.Artifact{Name: n, Digest: output.GetDigest(), SizeBytes: output.GetSizeBytes()})
	}
	return out
}

// run leases and completes tasks until ended is closed and nothing is left to lease,
// completing each with the outputs finish gives it; a task finish gives none is released
// (someone else's: a real worker's) and the worker pauses, to let others lease it.
func (lw *leaseWorker) run(t *testing.T, ctx context.Context, ended <-chan struct{}, finish func(*pb.LeaseTaskResponse) []*pb.Artifact) (cl completedLog) {
	if lw.id == "" {
		return cl
	}
	for {
		t0 := time.Now()
		resp, err := lw.ws.LeaseTask(ctx, &pb.LeaseTaskRequest{WorkerId: lw.id, WaitTimeout: durationpb.New(100 * time.Millisecond)})
		if err != nil {
			t.Errorf("worker %s: lease: %v", lw.id, err)
			return
		}
		if resp.GetLease() == nil {
			select {
			case <-ended:
				return
			default:
				continue
			}
		}
		cl.leases = append(cl.leases, time.Since(t0))
		cl.phases = append(cl.phases, resp.GetTask().GetPhase())
		outputs := finish(resp)
		if outputs == nil {
			if _, err := lw.ws.ReleaseTask(ctx, &pb.ReleaseTaskRequest{WorkerId: lw.id, TaskId: resp.GetLease().GetTaskId(), Epoch: resp.GetLease().GetEpoch()}); err != nil {
				t.Errorf("worker %s: release %s: %v", lw.id, resp.GetLease().GetTaskId(), err)
				return
			}
			time.Sleep(50 * time.Millisecond)
			continue
		}
		t1 := time.Now()
		_, err = lw.ws.CompleteTask(ctx, &pb.CompleteTaskRequest{WorkerId: lw.id, TaskId: resp.GetLease().GetTaskId(), Epoch: resp.GetLease().GetEpoch(), Outputs: outputs})
		if err != nil {
			t.Errorf("worker %s: complete %s: %v", lw.id, resp.GetLease().GetTaskId(), err)
			return
		}
		cl.completes = append(cl.completes, time.Since(t1))
		cl.tasks = append(cl.tasks, resp.GetLease().GetTaskId())
	}
}
