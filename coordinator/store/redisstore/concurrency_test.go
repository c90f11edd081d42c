package redisstore_test

import (
	"context"
	"fmt"
	"sync"
	"testing"
	"time"

	"photonfarm/coordinator/store"
	"photonfarm/coordinator/store/redisstore"
	"photonfarm/coordinator/store/redisstore/redistest"
	"photonfarm/coordinator/store/storetest"
	pb "photonfarm/proto/renderfarm/v1"
)

func newStore(t *testing.T, srv *redistest.Server, prefix string, opts store.Options) *redisstore.Store {
	t.Helper()
	s, err := redisstore.New(context.Background(), srv.Client(), prefix, opts)
	if err != nil {
		t.Fatal(err)
	}
	return s
}

// ledger checks what the lessees saw: no task leased by two at once, epochs growing,
// every task completed once.
type ledger struct {
	mu        sync.Mutex
	holder    map[string]string
	epoch     map[string]uint64
	completed map[string]int
}

func (l *ledger) leased(t *testing.T, worker string, ls *store.Leased) {
	l.mu.Lock()
	defer l.mu.Unlock()
	id := ls.Lease.TaskId
	if h := l.holder[id]; h != "" {
		t.Errorf("task %s leased to %s while %s holds it", id, worker, h)
	}
	if ls.Lease.Epoch <= l.epoch[id] {
		t.Errorf("task %s leased under epoch %d after epoch %d", id, ls.Lease.Epoch, l.epoch[id])
	}
	l.holder[id], l.epoch[id] = worker, ls.Lease.Epoch
}

// letGo is called before the report that gives the lease up, so that a lessee seen
// after it is no overlap.
func (l *ledger) letGo(id string) {
	l.mu.Lock()
	defer l.mu.Unlock()
	l.holder[id] = ""
}

func (l *ledger) done(id string) {
	l.mu.Lock()
	defer l.mu.Unlock()
	l.completed[id]++
}

// TestTwoReplicasNeverShareATask runs two Store values (two coordinators) on one Redis,
// each serving many lessees of one 500-tile job; some leases are released and leased
// again.
func TestTwoReplicasNeverShareATask(t *testing.T) {
	const tiles, lesseesPerReplica = 500, 12
	srv := redistest.Start(t)
	replicas := []*redisstore.Store{newStore(t, srv, "farm:", store.Options{}), newStore(t, srv, "farm:", store.Options{})}
	ctx := context.Background()
	j, err := replicas[0].CreateJob(ctx, storetest.TileJob("big", tiles))
	if err != nil {
		t.Fatal(err)
	}
	l := &ledger{holder: map[string]string{}, epoch: map[string]uint64{}, completed: map[string]int{}}
	var wg sync.WaitGroup
	for r, s := range replicas {
		for w := 0; w < lesseesPerReplica; w++ {
			wg.Add(1)
			go func(s *redisstore.Store, worker string) {
				defer wg.Done()
				for n := 0; ; n++ {
					ls, err := s.LeaseTask(ctx, worker, store.WorkerPhases)
					if err != nil {
						t.Error(err)
						return
					}
					if ls == nil {
						job, err := s.GetJob(ctx, j.Id)
						if err != nil || store.Ended(job.State) {
							return
						}
						time.Sleep(time.Millisecond) // the last tiles are still running
						continue
					}
					l.leased(t, worker, ls)
					time.Sleep(50 * time.Microsecond) // the work, while the lease is held
					l.letGo(ls.Lease.TaskId)
					ref := store.LeaseRef{WorkerID: worker, TaskID: ls.Lease.TaskId, Epoch: ls.Lease.Epoch}
					if n%7 == 3 {
						if _, err := s.ReleaseTask(ctx, ref); err != nil {
							t.Error(err)
						}
						continue
					}
					out := &pb.Artifact{Name: "tile.exr", Digest: "sha256:" + ls.Lease.TaskId}
					if _, err := s.CompleteTask(ctx, ref, []*pb.Artifact{out}); err != nil {
						t.Error(err)
						continue
					}
					l.done(ls.Lease.TaskId)
				}
			}(s, fmt.Sprintf("r%d-w%d", r, w))
		}
	}
	wg.Wait()
	if len(l.completed) != tiles+1 {
		t.Errorf("%d tasks completed, want %d", len(l.completed), tiles+1)
	}
	for id, n := range l.completed {
		if n != 1 {
			t.Errorf("task %s completed %d times", id, n)
		}
	}
	job, err := replicas[1].GetJob(ctx, j.Id)
	if err != nil || job.State != pb.JobState_JOB_STATE_SUCCEEDED {
		t.Fatalf("job = %v, %v; want SUCCEEDED", job, err)
	}
	if p := job.Phases[0]; p.TasksTotal != tiles || p.TasksSucceeded != tiles {
		t.Errorf("render progress = %v", p)
	}
}
