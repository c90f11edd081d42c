package redisstore_test

import (
	"context"
	"fmt"
	"strings"
	"sync/atomic"
	"testing"

	"photonfarm/coordinator/store"
	"photonfarm/coordinator/store/redisstore"
	"photonfarm/coordinator/store/redisstore/redistest"
	"photonfarm/coordinator/store/storetest"
)

// TestStore runs the behavioural suite, each case under a prefix of its own on one
// server.
func TestStore(t *testing.T) {
	srv := redistest.Start(t)
	rdb := srv.Client()
	var n atomic.Int64
	storetest.Run(t, func(t *testing.T, opts store.Options) store.Store {
		s, err := redisstore.New(context.Background(), rdb, fmt.Sprintf("case%d:", n.Add(1)), opts)
		if err != nil {
			t.Fatal(err)
		}
		return s
	})
}

// TestWorkers runs the registry's behavioural suite, each case under a prefix of its own.
func TestWorkers(t *testing.T) {
	srv := redistest.Start(t)
	rdb := srv.Client()
	var n atomic.Int64
	storetest.RunWorkers(t, func(t *testing.T) store.Workers {
		s, err := redisstore.New(context.Background(), rdb, fmt.Sprintf("workers%d:", n.Add(1)), store.Options{})
		if err != nil {
			t.Fatal(err)
		}
		return s.Workers()
	})
}

// TestAPrefixOfAnOlderLayoutIsRefused: keys written by the scripts of before issue 12
// (a job sequence, no layout key) make New fail naming the prefix, and stay as they were,
// instead of jobs failing midway; an empty prefix is claimed and opens again.
func TestAPrefixOfAnOlderLayoutIsRefused(t *testing.T) {
	srv := redistest.Start(t)
	rdb := srv.Client()
	ctx := context.Background()
	if err := rdb.Set(ctx, "old:seq", "7", 0).Err(); err != nil {
		t.Fatal(err)
	}
	if _, err := redisstore.New(ctx, rdb, "old:", store.Options{}); err == nil || !strings.Contains(err.Error(), `prefix "old:"`) {
		t.Errorf("New on keys of an older layout: %v, want a refusal naming the prefix", err)
	}
	if n, err := rdb.Exists(ctx, "old:layout").Result(); err != nil || n != 0 {
		t.Errorf("the refused prefix got a layout key (%d, %v): its keys must be left as they were", n, err)
	}
	for range 2 {
		if _, err := redisstore.New(ctx, rdb, "new:", store.Options{}); err != nil {
			t.Errorf("New on an empty prefix: %v", err)
		}
	}
}
