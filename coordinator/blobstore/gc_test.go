package blobstore_test

import (
	"context"
	"strings"
	"testing"
	"time"

	"photonfarm/coordinator/blobstore"
	"photonfarm/coordinator/errs"
)

// TestWalkTouchAndDeleteUnused: Walk lists every blob with its size and time; a blob older
// than the cutoff is deleted, one written or touched since is kept, and a touch of a blob
// that is gone says so. Object stores keep whole seconds, so the cutoff is taken once
// the old blobs' times have passed.
func TestWalkTouchAndDeleteUnused(t *testing.T) {
	forEachBackend(t, func(t *testing.T, open func(int64) (*blobstore.Store, raw)) {
		ctx := context.Background()
		s, raw := open(0)
		put := func(content string) string {
			info, err := s.Put(ctx, strings.NewReader(content), int64(len(content)), "")
			if err != nil {
				t.Fatal(err)
			}
			return info.Digest
		}
		walk := func() map[string]blobstore.Entry {
			seen := map[string]blobstore.Entry{}
			if err := s.Walk(ctx, func(e blobstore.Entry) error { seen[e.Digest] = e; return nil }); err != nil {
				t.Fatal(err)
			}
			return seen
		}
		old, touched := put("old"), put("touched")
		var latest time.Time
		for _, e := range walk() {
			if e.ModTime.After(latest) {
				latest = e.ModTime
			}
		}
		time.Sleep(time.Until(latest) + time.Millisecond)
		cutoff := time.Now()
		if _, err := s.Touch(ctx, touched); err != nil {
			t.Fatal(err)
		}
		fresh := put("fresh")

		seen := walk()
		if len(seen) != 3 || seen[old].Size != 3 || !seen[old].ModTime.Before(cutoff) || seen[touched].ModTime.Before(cutoff) {
			t.Fatalf("Walk saw %v; cutoff %v", seen, cutoff)
		}
		for d, want := range map[string]bool{old: true, touched: false, fresh: false} {
			if got, err := s.DeleteUnused(ctx, d, cutoff); err != nil || got != want {
				t.Errorf("DeleteUnused(%s) = %v, %v; want %v", d, got, err, want)
			}
		}
		if _, err := s.Stat(ctx, old); errs.KindOf(err) != errs.NotFound {
			t.Errorf("Stat of the deleted blob: %v", err)
		}
		if _, err := s.Touch(ctx, old); errs.KindOf(err) != errs.NotFound {
			t.Errorf("Touch of a deleted blob: %v, want NotFound", err)
		}
		for _, d := range []string{touched, fresh} {
			if _, err := s.Stat(ctx, d); err != nil {
				t.Errorf("Stat(%s) after the collection: %v", d, err)
			}
		}
		if left := raw.leftovers(t); len(left) != 0 {
			t.Errorf("left behind: %v", left)
		}
	})
}
