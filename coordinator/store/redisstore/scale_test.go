package redisstore_test

import (
	"context"
	"fmt"
	"regexp"
	"strconv"
	"strings"
	"testing"
	"time"

	"github.com/redis/go-redis/v9"

	"photonfarm/coordinator/retention"
	"photonfarm/coordinator/store"
	"photonfarm/coordinator/store/redisstore"
	"photonfarm/coordinator/store/redisstore/redistest"
	"photonfarm/coordinator/store/storetest"
	pb "photonfarm/proto/renderfarm/v1"
)

// storeOnItsOwnRedis starts a redis-server for the test alone and returns a store on it
// (prefix "farm:") and a client of it, to count what the store makes it do.
func storeOnItsOwnRedis(t *testing.T, opts store.Options) (*redisstore.Store, *redis.Client) {
	t.Helper()
	srv := redistest.Start(t)
	return newStore(t, srv, "farm:", opts), srv.Client()
}

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
	s, rdb := storeOnItsOwnRedis(t, store.Options{})
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
	s, rdb := storeOnItsOwnRedis(t, store.Options{})
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

// TestLargestRoundNeverBlocksRedis creates a job of the largest round validation allows
// (105,539 tasks), appends a second round of that size to another job with CompleteRound,
// leases from both, cancels them and purges them: each is done in scripts of about a
// millisecond, so that Redis never stops serving other clients for long. Every command the
// store sends is timed by the CPU Redis spent on it (redistest.CPUMeter), which must stay
// under 20 ms (one script writing such a job took over a second); the longest by CPU and
// by the slow log's clock (which a loaded machine stretches) are printed. tests/fault's
// TestJobAtTheLimitOnRedis renders such a job beside other clients.
func TestLargestRoundNeverBlocksRedis(t *testing.T) {
	const limit = 20 * time.Millisecond
	srv := redistest.Start(t)
	rdb, meter := srv.MeteredClient()
	s, err := redisstore.New(context.Background(), rdb, "farm:", store.Options{LeaseDuration: time.Hour})
	if err != nil {
		t.Fatal(err)
	}
	ctx := context.Background()
	srv.LogSlowCommands(time.Millisecond)
	meter.Worst()
	check := func(what string, t0 time.Time) {
		t.Helper()
		cpu, cmd := meter.Worst()
		clock, slow := srv.SlowestCommand()
		t.Logf("%s: %v; most CPU a command took %v %s; longest by the clock %v %s", what, time.Since(t0).Round(time.Millisecond), cpu, cmd, clock, slow)
		if cpu > limit {
			t.Errorf("%s: Redis spent %v of CPU on one command, want under %v", what, cpu, limit)
		}
	}
	lease := func() *store.Leased {
		t.Helper()
		l, err := s.LeaseTask(ctx, "w", append(store.WorkerPhases, store.BuilderPhases...))
		if err != nil || l == nil {
			t.Fatalf("LeaseTask = %v, %v", l, err)
		}
		return l
	}
	ref := func(l *store.Leased) store.LeaseRef {
		return store.LeaseRef{WorkerID: "w", TaskID: l.Lease.TaskId, Epoch: l.Lease.Epoch}
	}

	round := storetest.LargestRound(1)
	t0 := time.Now()
	big, err := s.CreateJob(ctx, store.NewJob{DisplayName: "largest", SceneDigest: "sha256:" + strings.Repeat("0", 64), Tasks: round})
	if err != nil {
		t.Fatal(err)
	}
	check(fmt.Sprintf("CreateJob of %d tasks", len(round)), t0)
	t0 = time.Now()
	if ts, _, err := s.ListTasks(ctx, big.Id, 10000, ""); err != nil || len(ts) != 10000 || ts[0].State != pb.TaskState_TASK_STATE_QUEUED {
		t.Fatalf("ListTasks = %d tasks, %v", len(ts), err)
	}
	check("ListTasks of 10,000", t0)

	small := storetest.TileJob("small", 1)
	small.Priority = store.MaxPriority
	progressive, err := s.CreateJob(ctx, small)
	if err != nil {
		t.Fatal(err)
	}
	if _, err := s.CompleteTask(ctx, ref(lease()), nil); err != nil {
		t.Fatal(err)
	}
	comp := lease()
	t0 = time.Now()
	if c, err := s.CompleteRound(ctx, ref(comp), store.RoundEnd{Report: &pb.RoundReport{Round: 1}, Next: storetest.LargestRound(2)}); err != nil || !c.Queued {
		t.Fatalf("CompleteRound = %+v, %v", c, err)
	}
	check(fmt.Sprintf("CompleteRound appending %d tasks", len(round)), t0)

	t0 = time.Now()
	for range 1000 {
		if _, err := s.CompleteTask(ctx, ref(lease()), nil); err != nil {
			t.Fatal(err)
		}
	}
	check("1,000 leases and completions", t0)
	for _, j := range []*pb.Job{big, progressive} {
		t0 = time.Now()
		if _, err := s.CancelJob(ctx, j.Id); err != nil {
			t.Fatal(err)
		}
		check("CancelJob", t0)
	}
	t0 = time.Now()
	var deleted []string
	for steps := 1; ; steps++ {
		p, err := s.PurgeJobs(ctx, time.Now().Add(time.Hour), time.Now(), retention.PurgeBudget)
		if err != nil {
			t.Fatal(err)
		}
		if deleted = append(deleted, p.Deleted...); !p.More {
			check(fmt.Sprintf("PurgeJobs of both in %d steps", steps), t0)
			break
		}
	}
	left, err := rdb.Keys(ctx, "farm:[tjrsqlp]:*").Result() // records, rounds, stages, queues, leases
	if err != nil || len(deleted) != 2 || len(left) != 0 {
		t.Errorf("after the purge: %v deleted, %d keys left (%v): %.200v", deleted, len(left), err, left)
	}
}
