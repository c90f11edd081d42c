package redisstore_test

import (
	"context"
	"testing"
	"time"

	"google.golang.org/protobuf/proto"

	"photonfarm/coordinator/clock"
	"photonfarm/coordinator/store"
	"photonfarm/coordinator/store/redisstore/redistest"
	"photonfarm/coordinator/store/storetest"
	pb "photonfarm/proto/renderfarm/v1"
)

// half leases every tile of a 6-tile job, completes three, and keeps the fourth's lease.
func half(t *testing.T, s store.Store, clk *clock.Fake) (*pb.Job, *store.Leased) {
	t.Helper()
	ctx := context.Background()
	j, err := s.CreateJob(ctx, storetest.TileJob("durable", 6))
	if err != nil {
		t.Fatal(err)
	}
	for i := 0; i < 3; i++ {
		l, err := s.LeaseTask(ctx, "w1", store.WorkerPhases)
		if err != nil || l == nil {
			t.Fatalf("LeaseTask = %v, %v", l, err)
		}
		if _, err := s.CompleteTask(ctx, store.LeaseRef{WorkerID: "w1", TaskID: l.Lease.TaskId, Epoch: l.Lease.Epoch}, nil); err != nil {
			t.Fatal(err)
		}
	}
	held, err := s.LeaseTask(ctx, "w1", store.WorkerPhases)
	if err != nil || held == nil {
		t.Fatalf("LeaseTask = %v, %v", held, err)
	}
	clk.Advance(time.Second)
	return j, held
}

// finish checks that s sees the job where half left it, then runs it to the end with
// the held lease and the remaining tiles.
func finish(t *testing.T, s store.Store, before *pb.Job, held *store.Leased) {
	t.Helper()
	ctx := context.Background()
	got, err := s.GetJob(ctx, before.Id)
	if err != nil {
		t.Fatal(err)
	}
	if !proto.Equal(got, before) {
		t.Fatalf("job after the restart = %v\nwant %v", got, before)
	}
	if got.Phases[0].TasksSucceeded != 3 || got.State != pb.JobState_JOB_STATE_RUNNING {
		t.Errorf("job = %v, want RUNNING with 3 tiles done", got)
	}
	// The lease granted before the restart is still the task's, under its epoch.
	if _, err := s.CompleteTask(ctx, store.LeaseRef{WorkerID: "w1", TaskID: held.Lease.TaskId, Epoch: held.Lease.Epoch}, nil); err != nil {
		t.Fatalf("complete under the lease granted before the restart: %v", err)
	}
	for leased := 0; ; leased++ {
		l, err := s.LeaseTask(ctx, "w2", store.WorkerPhases)
		if err != nil {
			t.Fatal(err)
		}
		if l == nil {
			if leased != 3 {
				t.Errorf("leased %d tasks after the restart, want the 2 tiles left and the composite", leased)
			}
			break
		}
		if _, err := s.CompleteTask(ctx, store.LeaseRef{WorkerID: "w2", TaskID: l.Lease.TaskId, Epoch: l.Lease.Epoch}, nil); err != nil {
			t.Fatal(err)
		}
	}
	if job, _ := s.GetJob(ctx, before.Id); job.GetState() != pb.JobState_JOB_STATE_SUCCEEDED {
		t.Errorf("job = %v, want SUCCEEDED", job)
	}
}

func TestStateSurvives(t *testing.T) {
	tests := []struct {
		name    string
		opts    []redistest.Option
		restart func(*redistest.Server)
	}{
		// A new coordinator (a new Store on a new connection) over the same Redis.
		{"CoordinatorRestart", nil, func(*redistest.Server) {}},
		// redis-server itself killed and started again from its append-only file.
		{"RedisRestartWithAOF", []redistest.Option{redistest.AppendOnly()}, (*redistest.Server).Restart},
	}
	for _, tt := range tests {
		t.Run(tt.name, func(t *testing.T) {
			srv := redistest.Start(t, tt.opts...)
			clk := clock.NewFake(time.Date(2030, 1, 2, 3, 4, 5, 0, time.UTC))
			opts := store.Options{Clock: clk, LeaseDuration: time.Minute}
			first := newStore(t, srv, "farm:", opts)
			j, held := half(t, first, clk)
			before, err := first.GetJob(context.Background(), j.Id)
			if err != nil {
				t.Fatal(err)
			}
			tt.restart(srv)
			finish(t, newStore(t, srv, "farm:", opts), before, held)
		})
	}
}

// TestEpochsOnlyGrowAcrossRestarts: a lease that expires before redis-server restarts is
// granted again afterwards under a larger epoch, so the old lessee stays fenced off.
func TestEpochsOnlyGrowAcrossRestarts(t *testing.T) {
	srv := redistest.Start(t, redistest.AppendOnly())
	clk := clock.NewFake(time.Date(2030, 1, 2, 3, 4, 5, 0, time.UTC))
	opts := store.Options{Clock: clk, LeaseDuration: time.Minute}
	ctx := context.Background()
	s := newStore(t, srv, "farm:", opts)
	if _, err := s.CreateJob(ctx, storetest.TileJob("fenced", 1)); err != nil {
		t.Fatal(err)
	}
	old, err := s.LeaseTask(ctx, "w1", store.WorkerPhases)
	if err != nil || old == nil {
		t.Fatalf("LeaseTask = %v, %v", old, err)
	}
	clk.Advance(time.Minute)
	if cs, err := s.ExpireLeases(ctx); err != nil || len(cs) != 1 {
		t.Fatalf("ExpireLeases = %v, %v", cs, err)
	}
	srv.Restart()
	s = newStore(t, srv, "farm:", opts)
	again, err := s.LeaseTask(ctx, "w2", store.WorkerPhases)
	if err != nil || again == nil || again.Lease.TaskId != old.Lease.TaskId || again.Lease.Epoch <= old.Lease.Epoch {
		t.Fatalf("lease after the restart = %v, %v; want %s under an epoch above %d", again, err, old.Lease.TaskId, old.Lease.Epoch)
	}
	if _, err := s.CompleteTask(ctx, store.LeaseRef{WorkerID: "w1", TaskID: old.Lease.TaskId, Epoch: old.Lease.Epoch}, nil); err == nil {
		t.Error("the expired lessee completed the task after the restart")
	}
}
