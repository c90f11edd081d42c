package store_test

import (
	"testing"
	"time"

	"photonfarm/coordinator/store"
)

func TestBackoffDoublesUpToTheCap(t *testing.T) {
	o := store.Options{}.WithDefaults()
	for _, tc := range []struct {
		failures int
		want     time.Duration
	}{
		{1, time.Second},
		{2, 2 * time.Second},
		{3, 4 * time.Second},
		{6, 32 * time.Second},
		{7, time.Minute},
		{1000, time.Minute},
	} {
		if got := o.Backoff(tc.failures); got != tc.want {
			t.Errorf("Backoff(%d) = %v, want %v", tc.failures, got, tc.want)
		}
	}
}

func TestCheckPriority(t *testing.T) {
	for p, ok := range map[int32]bool{-1001: false, -1000: true, 0: true, 1000: true, 1001: false} {
		if err := store.CheckPriority(p); (err == nil) != ok {
			t.Errorf("CheckPriority(%d) = %v", p, err)
		}
	}
}
