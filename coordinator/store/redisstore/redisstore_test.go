package redisstore_test

import (
	"context"
	"fmt"
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
