package redisstore_test

import (
	"context"
	"regexp"
	"strconv"
	"testing"

	"github.com/redis/go-redis/v9"

	"photonfarm/coordinator/store"
	"photonfarm/coordinator/store/redisstore/redistest"
	"photonfarm/coordinator/store/storetest"
	pb "photonfarm/proto/renderfarm/v1"
)

// commands counts the commands Redis ran since the last count (those run by scripts
// included), from INFO commandstats.
func commands(t *testing.T, rdb *redis.Client) int {
	t.Helper()
	ctx := context.Background()
	info, err := rdb.Info(ctx, "commandstats").Result()
	if err != nil {
		t.Fatal(err)
	}
	if err := rdb.ConfigResetStat(ctx).Err(); err != nil {
		t.Fatal(err)
	}
	n := 0
	for _, m := range regexp.MustCompile(`calls=(\d+)`).FindAllStringSubmatch(info, -1) {
		c, _ := strconv.Atoi(m[1])
		n += c
	}
	return n
}

// TestLeaseAndCompleteDoNotScanTheJob: in a job of 10,000 tiles, a lease and a completion
// run a few dozen Redis commands, not one per task.
func TestLeaseAndCompleteDoNotScanTheJob(t *testing.T) {
	const tiles, budget = 10000, 60
	srv := redistest.Start(t)
	rdb := srv.Client()
	s := newStore(t, srv, "farm:", store.Options{})
	ctx := context.Background()
	if _, err := s.CreateJob(ctx, storetest.TileJob("huge", tiles)); err != nil {
		t.Fatal(err)
	}
	for i := 0; i < 3; i++ {
		commands(t, rdb)
		l, err := s.LeaseTask(ctx, "w1", store.WorkerPhases)
		if err != nil || l == nil {
			t.Fatalf("LeaseTask = %v, %v", l, err)
		}
		if n := commands(t, rdb); n > budget {
			t.Errorf("a lease ran %d commands, want at most %d", n, budget)
		}
		if _, err := s.CompleteTask(ctx, store.LeaseRef{WorkerID: "w1", TaskID: l.Lease.TaskId, Epoch: l.Lease.Epoch}, nil); err != nil {
			t.Fatal(err)
		}
		if n := commands(t, rdb); n > budget {
			t.Errorf("a completion ran %d commands, want at most %d", n, budget)
		}
	}
}

// TestOpeningAStageAndCancellingDoNotTouchEveryTask: the build's completion queues 10,000
// tiles, and cancelling the job then drops them, each in a few dozen commands: the
// stage's tasks are a range, not written one by one, and a cancelled job's tasks read as
// cancelled without being rewritten.
func TestOpeningAStageAndCancellingDoNotTouchEveryTask(t *testing.T) {
	const tiles, budget = 10000, 60
	srv := redistest.Start(t)
	rdb := srv.Client()
	s := newStore(t, srv, "farm:", store.Options{})
	ctx := context.Background()
	nj := storetest.TileJob("staged", tiles)
	emit := &pb.Task{Phase: pb.Phase_PHASE_EMIT, Spec: &pb.Task_EmitPhotons{EmitPhotons: &pb.EmitPhotonsSpec{PhotonCount: 1000, TotalPhotons: 1000}}}
	build := &pb.Task{Phase: pb.Phase_PHASE_BUILD, Spec: &pb.Task_BuildPhotonMap{BuildPhotonMap: &pb.BuildPhotonMapSpec{}}}
	nj.Tasks = append([]*pb.Task{emit, build}, nj.Tasks...)
	for i, task := range nj.Tasks {
		task.Index = uint32(i)
	}
	j, err := s.CreateJob(ctx, nj)
	if err != nil {
		t.Fatal(err)
	}
	for _, phases := range [][]pb.Phase{store.WorkerPhases, store.BuilderPhases} {
		l, err := s.LeaseTask(ctx, "w1", phases)
		if err != nil || l == nil {
			t.Fatalf("LeaseTask = %v, %v", l, err)
		}
		commands(t, rdb)
		c, err := s.CompleteTask(ctx, store.LeaseRef{WorkerID: "w1", TaskID: l.Lease.TaskId, Epoch: l.Lease.Epoch}, nil)
		if err != nil || !c.Queued {
			t.Fatalf("CompleteTask(%s) = %+v, %v; want the next stage queued", l.Lease.TaskId, c, err)
		}
		if n := commands(t, rdb); n > budget {
			t.Errorf("completing %s (opening the next stage) ran %d commands, want at most %d", l.Lease.TaskId, n, budget)
		}
	}
	if l, err := s.LeaseTask(ctx, "w1", store.WorkerPhases); err != nil || l.Task.GetRenderTile() == nil {
		t.Fatalf("LeaseTask = %v, %v; want a tile", l, err)
	}
	commands(t, rdb)
	if _, err := s.CancelJob(ctx, j.Id); err != nil {
		t.Fatal(err)
	}
	if n := commands(t, rdb); n > budget {
		t.Errorf("cancelling a job of %d queued tiles ran %d commands, want at most %d", tiles, n, budget)
	}
	ts, _, err := s.ListTasks(ctx, j.Id, 5, "")
	if err != nil {
		t.Fatal(err)
	}
	for i, want := range []pb.TaskState{pb.TaskState_TASK_STATE_SUCCEEDED, pb.TaskState_TASK_STATE_SUCCEEDED,
		pb.TaskState_TASK_STATE_CANCELLED, pb.TaskState_TASK_STATE_CANCELLED, pb.TaskState_TASK_STATE_CANCELLED} {
		if ts[i].State != want {
			t.Errorf("task %d is %v, want %v", i, ts[i].State, want)
		}
	}
}
