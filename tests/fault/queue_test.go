package fault

import (
	"context"
	"flag"
	"fmt"
	"testing"
	"time"

	"photonfarm/coordinator/store"
	"photonfarm/coordinator/store/memstore"
	"photonfarm/coordinator/store/redisstore"
	"photonfarm/coordinator/store/redisstore/redistest"
	"photonfarm/coordinator/store/storetest"
)

// Issue 12's acceptance 3: LeaseTask with a million tasks queued.
var queuedTasks = flag.Int("queued-tasks", 1_000_000, "tasks queued in each store by TestLeaseWithAMillionTasksQueued (issue 12: 1,000,000)")

// TestLeaseWithAMillionTasksQueued queues -queued-tasks render tasks (in jobs of 65,536
// tiles, the most a round may have) in the in-memory store and in Redis, then has 4 fake
// workers lease and complete tasks, each held 2 ms, for 2,000 leases, and submits a
// 16-tile job at priority 1000: LeaseTask's p99 must stay under 10 ms (the figure),
// and the small job must finish in about the time it takes on an empty store (at most
// three times that and 250 ms). It prints p50, p99 and max and both times.
func TestLeaseWithAMillionTasksQueued(t *testing.T) {
	t.Run("memory", func(t *testing.T) {
		queuedLeases(t, func(opts store.Options) store.Store { return memstore.New(opts) })
	})
	t.Run("redis", func(t *testing.T) {
		rdb := redistest.Start(t).Client()
		n := 0
		queuedLeases(t, func(opts store.Options) store.Store {
			n++
			s, err := redisstore.New(context.Background(), rdb, fmt.Sprintf("queued%d:", n), opts)
			if err != nil {
				t.Fatal(err)
			}
			return s
		})
	})
}

func queuedLeases(t *testing.T, newStore func(store.Options) store.Store) {
	const (
		perJob, workers, leases = 65536, 4, 2000
		smallTiles              = 16
		taskTime                = 2 * time.Millisecond
		leaseP99                = 10 * time.Millisecond
	)
	opts := store.Options{LeaseDuration: time.Hour}
	alone, _ := storetest.UrgentJob(t, newStore(opts), smallTiles, workers, taskTime)
	s := newStore(opts)
	t0 := time.Now()
	jobs := storetest.Fill(t, s, *queuedTasks, perJob)
	t.Logf("%d tasks queued in %d jobs in %v", *queuedTasks, len(jobs), time.Since(t0).Round(time.Millisecond))
	lat := storetest.Leases(t, s, workers, leases, taskTime)
	busy, _ := storetest.UrgentJob(t, s, smallTiles, workers, taskTime)
	t.Logf("LeaseTask with %d tasks queued: %v", *queuedTasks, lat)
	t.Logf("%d-tile job at priority 1000: %v on an empty store, %v beside the backlog", smallTiles,
		alone.Round(time.Millisecond), busy.Round(time.Millisecond))
	if p99 := lat.Pct(99); p99 > leaseP99 {
		t.Errorf("LeaseTask p99 %v with %d tasks queued, want under %v", p99, *queuedTasks, leaseP99)
	}
	if limit := 3*alone + 250*time.Millisecond; busy > limit {
		t.Errorf("the small job took %v beside the backlog, %v alone: want at most %v", busy, alone, limit)
	}
}
