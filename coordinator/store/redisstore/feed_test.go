package redisstore_test

import (
	"context"
	"sync"
	"testing"
	"time"

	"photonfarm/coordinator/store"
	"photonfarm/coordinator/store/redisstore"
	"photonfarm/coordinator/store/redisstore/redistest"
	"photonfarm/coordinator/store/storetest"
	pb "photonfarm/proto/renderfarm/v1"
)

// follower collects what Follow hands a replica.
type follower struct {
	mu   sync.Mutex
	seen []store.Remote
}

func follow(t *testing.T, ctx context.Context, s *redisstore.Store) *follower {
	t.Helper()
	f := &follower{}
	started := make(chan struct{})
	go func() {
		close(started)
		_ = s.Follow(ctx, func(r store.Remote) {
			f.mu.Lock()
			defer f.mu.Unlock()
			f.seen = append(f.seen, r)
		})
	}()
	<-started
	time.Sleep(200 * time.Millisecond) // Follow reads the feed's end before the changes below
	return f
}

// waitFor returns the changes followed once one names task id (or fails after 10 s).
func (f *follower) waitFor(t *testing.T, id string, n int) []store.Remote {
	t.Helper()
	for deadline := time.Now().Add(10 * time.Second); time.Now().Before(deadline); time.Sleep(10 * time.Millisecond) {
		f.mu.Lock()
		count := 0
		for _, r := range f.seen {
			if r.TaskID == id {
				count++
			}
		}
		seen := append([]store.Remote(nil), f.seen...)
		f.mu.Unlock()
		if count >= n {
			return seen
		}
	}
	t.Fatalf("task %s was not followed %d times within 10 s", id, n)
	return nil
}

// TestAReplicaFollowsTheOthersChanges: replica B hears of every change replica A makes,
// in order, including one whose answer A never got (the connection dropped after Redis
// ran the script, as when a coordinator dies right after its write); A hears nothing of
// its own; Load reads the job and task as they stand.
func TestAReplicaFollowsTheOthersChanges(t *testing.T) {
	srv := redistest.Start(t)
	proxy := srv.Proxy()
	a, err := redisstore.New(context.Background(), proxy.Client(), "farm:", store.Options{})
	if err != nil {
		t.Fatal(err)
	}
	b := newStore(t, srv, "farm:", store.Options{})
	ctx, cancel := context.WithCancel(context.Background())
	defer cancel()
	ofB, ofA := follow(t, ctx, b), follow(t, ctx, a)

	j, err := a.CreateJob(ctx, storetest.TileJob("followed", 2))
	if err != nil {
		t.Fatal(err)
	}
	ls, err := a.LeaseTask(ctx, "w1", store.WorkerPhases)
	if err != nil || ls == nil {
		t.Fatalf("lease = %v, %v", ls, err)
	}
	ref := store.LeaseRef{WorkerID: "w1", TaskID: ls.Lease.TaskId, Epoch: ls.Lease.Epoch}
	// A's completion runs in Redis, and its answer is lost; A retries under the same
	// operation key and gets the one run's answer, so the feed holds one completion.
	proxy.CutReplyTo("sha256:done", 1)
	if _, err := a.CompleteTask(ctx, ref, []*pb.Artifact{{Name: "tile.exr", Digest: "sha256:done"}}); err != nil {
		t.Fatal(err)
	}
	if proxy.Cuts() != 1 {
		t.Fatalf("the proxy cut %d answers, want 1", proxy.Cuts())
	}
	seen := ofB.waitFor(t, ref.TaskID, 2)
	var kinds []string
	for _, r := range seen {
		if r.JobID != j.Id {
			t.Errorf("followed a change of job %q, want only %s's", r.JobID, j.Id)
		}
		if r.TaskID == ref.TaskID {
			c, err := r.Load(ctx)
			if err != nil {
				t.Fatal(err)
			}
			kinds = append(kinds, c.Task.GetState().String())
			if c.Job.GetId() != j.Id || c.Task.GetId() != ref.TaskID {
				t.Errorf("Load = job %q task %q, want %s and %s", c.Job.GetId(), c.Task.GetId(), j.Id, ref.TaskID)
			}
		}
	}
	if len(kinds) != 2 {
		t.Errorf("task %s followed %d times (%v), want twice: its lease and its one completion", ref.TaskID, len(kinds), kinds)
	}
	time.Sleep(1500 * time.Millisecond) // longer than one blocking read of the feed
	ofA.mu.Lock()
	defer ofA.mu.Unlock()
	if len(ofA.seen) != 0 {
		t.Errorf("replica A followed %d changes of its own, want none", len(ofA.seen))
	}
}
