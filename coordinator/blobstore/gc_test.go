package blobstore_test

import (
	"context"
	"testing"
	"time"

	"photonfarm/coordinator/blobstore"
	"photonfarm/coordinator/blobstore/blobtest"
	"photonfarm/coordinator/errs"
)

// TestWalkTouchAndDeleteUnused: Walk lists every blob with its size and time; a blob older
// than the cutoff is deleted, one written or touched since is kept, and a touch of a blob
// that is gone says so.
func TestWalkTouchAndDeleteUnused(t *testing.T) {
	ctx := context.Background()
	s := blobtest.New(t)
	old, touched, fresh := s.Put("old"), s.Put("touched"), s.Put("fresh")
	s.Age(time.Now().Add(-48*time.Hour), old, touched)
	cutoff := time.Now().Add(-24 * time.Hour)
	if _, err := s.Touch(ctx, touched); err != nil {
		t.Fatal(err)
	}

	seen := map[string]blobstore.Entry{}
	if err := s.Walk(ctx, func(e blobstore.Entry) error { seen[e.Digest] = e; return nil }); err != nil {
		t.Fatal(err)
	}
	if len(seen) != 3 || seen[old].Size != 3 || !seen[old].ModTime.Before(cutoff) || seen[touched].ModTime.Before(cutoff) {
		t.Fatalf("Walk saw %v", seen)
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
	if left := s.Temp(); len(left) != 0 {
		t.Errorf("left in tmp: %v", left)
	}
}
