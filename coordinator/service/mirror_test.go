package service

import (
	"bytes"
	"context"
	"errors"
	"log/slog"
	"strings"
	"testing"
	"time"
)

// TestRegistryWritesOutliveTheCallersCancellation: the worker registry records what the
// store committed even when the worker's call was cancelled meanwhile (a worker that gave
// up waiting still holds the lease the store gave it), keeps the caller's values, gives
// up after mirrorTimeout, and a write that fails is logged naming what was not recorded.
func TestRegistryWritesOutliveTheCallersCancellation(t *testing.T) {
	type key struct{}
	var logged bytes.Buffer
	s := &Service{log: slog.New(slog.NewTextHandler(&logged, nil))}
	caller, cancel := context.WithCancel(context.WithValue(context.Background(), key{}, "worker-1"))
	cancel()

	// The write fails (and is logged) if it sees the caller's cancellation.
	var seen context.Context
	s.mirror(caller, "a lease", func(ctx context.Context) error {
		seen = ctx
		return ctx.Err()
	})
	deadline, ok := seen.Deadline()
	if !ok || time.Until(deadline) > mirrorTimeout {
		t.Errorf("the registry write has no deadline within %v (deadline %v, set %t)", mirrorTimeout, deadline, ok)
	}
	if seen.Value(key{}) != "worker-1" {
		t.Errorf("the registry write lost the caller's values")
	}
	if logged.Len() != 0 {
		t.Errorf("a write under a cancelled call failed: %s", logged.String())
	}

	s.mirror(caller, "a completion", func(context.Context) error { return errors.New("redis: connection refused") })
	if got := logged.String(); !strings.Contains(got, "worker registry: cannot record a completion") || !strings.Contains(got, "connection refused") {
		t.Errorf("a failed registry write logged %q", got)
	}
}
