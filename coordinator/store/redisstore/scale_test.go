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
