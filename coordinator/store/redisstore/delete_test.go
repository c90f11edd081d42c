package redisstore_test

import (
	"context"
	"testing"
	"time"

	"photonfarm/coordinator/store"
	"photonfarm/coordinator/store/redisstore"
	"photonfarm/coordinator/store/redisstore/redistest"
	"photonfarm/coordinator/store/storetest"
)

// TestDeletedJobLeavesNoKeysAfterItsPurge: DeleteJob, then purge steps with no cutoff
// (what the service runs), leave no record, round list, stage map, queue or lease set of
// the job, however it stood: leased, with a queue of tasks put back, reopened, ended.
func TestDeletedJobLeavesNoKeysAfterItsPurge(t *testing.T) {
	srv := redistest.Start(t)
	rdb := srv.Client()
	ctx := context.Background()
	for _, tt := range []struct {
		name  string
		setup func(t *testing.T, s store.Store, job string)
	}{
		{"Queued", func(*testing.T, store.Store, string) {}},
		{"WithLeasesAndATaskPutBack", func(t *testing.T, s store.Store, job string) {
			l, err := s.LeaseTask(ctx, "w1", store.WorkerPhases)
			if err != nil || l == nil {
				t.Fatalf("LeaseTask = %v, %v", l, err)
			}
			if _, err := s.LeaseTask(ctx, "w2", store.WorkerPhases); err != nil {
				t.Fatal(err)
			}
			if _, err := s.ReleaseTask(ctx, store.LeaseRef{WorkerID: "w1", TaskID: l.Lease.TaskId, Epoch: l.Lease.Epoch}); err != nil {
				t.Fatal(err)
			}
		}},
		{"CancelledThenRequeued", func(t *testing.T, s store.Store, job string) {
			if _, err := s.LeaseTask(ctx, "w1", store.WorkerPhases); err != nil {
				t.Fatal(err)
			}
			if _, err := s.CancelJob(ctx, job); err != nil {
				t.Fatal(err)
			}
			if _, err := s.ReopenJob(ctx, job, ""); err != nil {
				t.Fatal(err)
			}
		}},
	} {
		t.Run(tt.name, func(t *testing.T) {
			prefix := "del-" + tt.name + ":"
			s, err := redisstore.New(ctx, rdb, prefix, store.Options{})
			if err != nil {
				t.Fatal(err)
			}
			j, err := s.CreateJob(ctx, storetest.TileJob("a", 4))
			if err != nil {
				t.Fatal(err)
			}
			tt.setup(t, s, j.Id)
			if _, err := s.DeleteJob(ctx, j.Id); err != nil {
				t.Fatal(err)
			}
			for step := 0; ; step++ {
				p, err := s.PurgeJobs(ctx, time.Time{}, time.Time{}, 2)
				if err != nil || step > 100 {
					t.Fatalf("PurgeJobs step %d: %v", step, err)
				}
				if !p.More {
					break
				}
			}
			left, err := rdb.Keys(ctx, prefix+"[tjrsqlp]:*").Result()
			if err != nil || len(left) != 0 {
				t.Errorf("after the delete and its purge: %d keys left (%v): %v", len(left), err, left)
			}
			for _, k := range []string{"jobs", "ended", "doomed", "leases"} {
				if n, err := rdb.ZCard(ctx, prefix+k).Result(); err != nil || n != 0 {
					t.Errorf("%s%s holds %d members (%v), want none", prefix, k, n, err)
				}
			}
			ready, err := rdb.Keys(ctx, prefix+"ready:*").Result()
			if err != nil {
				t.Fatal(err)
			}
			for _, k := range ready {
				if n, err := rdb.ZCard(ctx, k).Result(); err != nil || n != 0 {
					t.Errorf("%s holds %d members (%v), want none", k, n, err)
				}
			}
		})
	}
}
