package blobstore

import (
	"context"
	"time"
)

// What a garbage collector of blobs needs (coordinator/retention): every blob with the
// time it was last written or marked in use, and a delete that never takes a blob marked
// in use after a given time.
//
// The protocol that keeps a blob a job is about to reference: whoever makes a reference
// (a submit naming a mesh, a completion naming an output) first calls Touch, which sets
// the blob's modification time to now, and then checks it exists; the collector deletes
// only blobs modified before its cutoff (now minus a grace period, taken before it lists
// the references), and DeleteUnused checks the time again after moving the blob out of
// reach. A Touch that comes before that move is seen by the check, and the blob put back;
// one that comes after finds no blob, and its caller refuses the reference ("upload it
// first") instead of recording one to a blob that is going.

// Entry is a stored blob as a collector sees it.
type Entry struct {
	Digest  string
	Size    int64
	ModTime time.Time // when it was last written or touched
}

// Walk calls fn with every stored blob, in no particular order, until fn returns an error,
// which Walk returns.
func (s *Store) Walk(ctx context.Context, fn func(Entry) error) error { return s.b.walk(ctx, fn) }

// Touch marks a blob in use now, so that a collector keeps it for its grace period, and
// returns it as Stat does (errs.NotFound if it does not exist).
func (s *Store) Touch(ctx context.Context, digest string) (Info, error) {
	if err := checkDigest("digest", digest); err != nil {
		return Info{}, err
	}
	if err := s.b.touch(ctx, digest); err != nil {
		return Info{}, err
	}
	return s.Stat(ctx, digest)
}

// DeleteUnused deletes a blob unless it was written or touched at or after before, and
// reports whether it did. The blob is first moved out of reach, and its time checked
// again there: a blob touched meanwhile is put back.
func (s *Store) DeleteUnused(ctx context.Context, digest string, before time.Time) (bool, error) {
	if err := checkDigest("digest", digest); err != nil {
		return false, err
	}
	return s.b.deleteUnused(ctx, digest, before)
}
