package integration

import (
	"context"
	"strings"
	"sync"
	"testing"
	"time"

	"google.golang.org/grpc"
	"google.golang.org/grpc/credentials/insecure"

	"photonfarm/client"
	"photonfarm/contract/scene/scenetest"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

// brokenWorker plays a worker that fails every task it leases as transient with reason
// (a healthy-looking host whose GPU is gone), heartbeating, until ctx ends.
func brokenWorker(ctx context.Context, t *testing.T, w pb.WorkerServiceClient, reason string) {
	reg, err := w.RegisterWorker(ctx, &pb.RegisterWorkerRequest{Hostname: "broken"})
	if err != nil {
		t.Errorf("RegisterWorker: %v", err)
		return
	}
	id := reg.GetWorkerId()
	for ctx.Err() == nil {
		if _, err := w.Heartbeat(ctx, &pb.HeartbeatRequest{WorkerId: id}); err != nil && ctx.Err() == nil {
			t.Errorf("Heartbeat: %v", err)
			return
		}
		poll, cancel := context.WithTimeout(ctx, 500*time.Millisecond) // shorter than a lease duration: stays live
		l, err := w.LeaseTask(poll, &pb.LeaseTaskRequest{WorkerId: id})
		cancel()
		if err != nil || l.GetLease() == nil {
			continue // nothing to lease, or blocked from the job
		}
		if _, err := w.FailTask(ctx, &pb.FailTaskRequest{WorkerId: id, TaskId: l.GetLease().GetTaskId(),
			Epoch: l.GetLease().GetEpoch(), Error: reason, Kind: pb.FailureKind_FAILURE_KIND_TRANSIENT}); err != nil && ctx.Err() == nil {
			t.Errorf("FailTask: %v", err)
			return
		}
	}
}

// A job that no live worker of the farm can run fails with the reason within 30 seconds
// (issue 12, acceptance 6) rather than staying RUNNING for ever: when the last worker is
// blocked from it, or when the last worker not blocked is lost later (the coordinator's
// sweep).
func TestJobNoWorkerCanRunFailsWithTheReasonWithin30Seconds(t *testing.T) {
	const reason = "CUDA error: the GPU has fallen off the bus"
	for _, tt := range []struct {
		name          string
		broken        int
		passerBy      bool // a worker that never leases, lost once the broken ones are blocked
		wantErrPrefix string
	}{
		{"every worker fails it", 2, false, "every worker (2) is blocked from this job; last: 3 failed tasks: " + reason},
		{"the last other worker is lost after the block", 1, true, "every worker (1) is blocked from this job; last: 3 failed tasks: " + reason},
	} {
		t.Run(tt.name, func(t *testing.T) {
			f := farmtest.StartFarm(t, nil)
			sc := scenetest.Unlit(256, 64)
			sc.Film.TileSize = 32 // 16 tiles: three failures of each worker land on different tiles
			job := f.Submit(t, sc)
			conn, err := grpc.NewClient(f.Addr, grpc.WithTransportCredentials(insecure.NewCredentials()), client.WorkerSecrets())
			if err != nil {
				t.Fatal(err)
			}
			defer conn.Close()
			w := pb.NewWorkerServiceClient(conn)
			ctx, stop := context.WithCancel(context.Background())
			var wg sync.WaitGroup
			defer wg.Wait()
			defer stop()
			start := time.Now()
			run := func(fn func()) {
				wg.Add(1)
				go func() {
					defer wg.Done()
					fn()
				}()
			}
			die := func() {}
			if tt.passerBy {
				reg, err := w.RegisterWorker(ctx, &pb.RegisterWorkerRequest{Hostname: "passer-by"})
				if err != nil {
					t.Fatal(err)
				}
				var alive context.Context
				alive, die = context.WithCancel(ctx)
				run(func() { heartbeat(alive, w, reg.GetWorkerId()) })
			}
			for range tt.broken {
				run(func() { brokenWorker(ctx, t, w, reason) })
			}
			if tt.passerBy {
				waitBlocked(t, f, job.GetId(), tt.broken)
				if got, err := f.Client.GetJob(ctx, job.GetId()); err != nil || got.GetState() != pb.JobState_JOB_STATE_RUNNING {
					t.Fatalf("job %v, %v while the passer-by may still run it, want RUNNING", got.GetState(), err)
				}
			}
			die() // the passer-by is lost a lease duration later
			watch, cancel := context.WithTimeout(ctx, 30*time.Second-time.Since(start))
			defer cancel()
			ended, err := f.Client.Watch(watch, job.GetId(), nil)
			if err != nil {
				last, _ := f.Client.GetJob(ctx, job.GetId())
				t.Fatalf("job %s did not end within 30 s: %v (last seen: %v)", job.GetId(), err, last)
			}
			t.Logf("job %v after %s: %s", ended.GetState(), time.Since(start).Round(time.Millisecond), ended.GetError())
			if ended.GetState() != pb.JobState_JOB_STATE_FAILED || !strings.HasPrefix(ended.GetError(), tt.wantErrPrefix) {
				t.Errorf("job %v %q, want FAILED with %q", ended.GetState(), ended.GetError(), tt.wantErrPrefix)
			}
			if n := len(ended.GetBlockedWorkers()); n != tt.broken {
				t.Errorf("%d blocked workers, want %d", n, tt.broken)
			}
		})
	}
}

// heartbeat keeps worker id heard from until ctx ends.
func heartbeat(ctx context.Context, w pb.WorkerServiceClient, id string) {
	for ctx.Err() == nil {
		_, _ = w.Heartbeat(ctx, &pb.HeartbeatRequest{WorkerId: id})
		select {
		case <-ctx.Done():
		case <-time.After(200 * time.Millisecond):
		}
	}
}

// waitBlocked waits up to 20 s for n workers to be blocked from jobID.
func waitBlocked(t *testing.T, f *farmtest.Farm, jobID string, n int) {
	t.Helper()
	for deadline := time.Now().Add(20 * time.Second); ; time.Sleep(50 * time.Millisecond) {
		job, err := f.Client.GetJob(context.Background(), jobID)
		if err != nil {
			t.Fatal(err)
		}
		if len(job.GetBlockedWorkers()) >= n {
			return
		}
		if time.Now().After(deadline) {
			t.Fatalf("job %v: %d workers blocked after 20 s, want %d", job.GetState(), len(job.GetBlockedWorkers()), n)
		}
	}
}
