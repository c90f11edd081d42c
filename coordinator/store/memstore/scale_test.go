package memstore_test

import (
	"testing"
	"time"

	"photonfarm/coordinator/store"
	"photonfarm/coordinator/store/memstore"
	"photonfarm/coordinator/store/storetest"
)

// TestUrgentJobIsNotSlowedByAQueuedBacklog: with 200,000 tasks queued (the full million is
// tests/fault's TestLeaseWithAMillionTasksQueued), a 64-tile job at the highest priority
// finishes in about the time it takes alone, and LeaseTask stays fast. A lease that
// scanned the queued tasks under the store's lock took tens of times longer.
func TestUrgentJobIsNotSlowedByAQueuedBacklog(t *testing.T) {
	const (
		queued, perJob = 200000, 65536
		tiles, workers = 64, 4
		taskTime       = 2 * time.Millisecond
	)
	alone, _ := storetest.UrgentJob(t, memstore.New(store.Options{}), tiles, workers, taskTime)
	s := memstore.New(store.Options{})
	storetest.Fill(t, s, queued, perJob)
	lat := storetest.Leases(t, s, workers, 2000, taskTime)
	busy, _ := storetest.UrgentJob(t, s, tiles, workers, taskTime)
	t.Logf("with %d tasks queued: LeaseTask %v; urgent job of %d tiles on %d workers: %v alone, %v with the backlog", queued, lat,
		tiles, workers, alone.Round(time.Millisecond), busy.Round(time.Millisecond))
	// Generous margins: the machine is shared. Alone it takes tiles/workers tasks.
	if busy > 3*alone+time.Second {
		t.Errorf("with %d tasks queued the urgent job took %v, alone %v", queued, busy, alone)
	}
	if p99 := lat.Pct(99); p99 > 10*time.Millisecond {
		t.Errorf("LeaseTask p99 %v with %d tasks queued, want under 10ms", p99, queued)
	}
}
