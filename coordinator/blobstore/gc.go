package blobstore

import (
	"context"
	"errors"
	"io/fs"
	"os"
	"path/filepath"
	"time"

	"photonfarm/contract/rules"
	"photonfarm/coordinator/errs"
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
func (s *Store) Walk(ctx context.Context, fn func(Entry) error) error {
	return filepath.WalkDir(filepath.Join(s.root, "sha256"), func(path string, d fs.DirEntry, err error) error {
		if err != nil {
			return errs.Wrap(errs.Internal, err, "blobstore")
		}
		if err := ctx.Err(); err != nil {
			return err
		}
		digest := "sha256:" + d.Name()
		if d.IsDir() || !rules.ValidDigest(digest) {
			return nil
		}
		fi, err := d.Info()
		if errors.Is(err, fs.ErrNotExist) {
			return nil // deleted meanwhile
		}
		if err != nil {
			return errs.Wrap(errs.Internal, err, "blobstore")
		}
		return fn(Entry{Digest: digest, Size: fi.Size(), ModTime: fi.ModTime()})
	})
}

// Touch marks a blob in use now, so that a collector keeps it for its grace period, and
// returns it as Stat does (errs.NotFound if it does not exist).
func (s *Store) Touch(ctx context.Context, digest string) (Info, error) {
	if err := checkDigest("digest", digest); err != nil {
		return Info{}, err
	}
	now := time.Now()
	if err := os.Chtimes(s.path(digest), now, now); err != nil && !errors.Is(err, fs.ErrNotExist) {
		return Info{}, errs.Wrap(errs.Internal, err, "blobstore")
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
	path := s.path(digest)
	fi, err := os.Stat(path)
	if errors.Is(err, fs.ErrNotExist) {
		return false, nil
	}
	if err != nil {
		return false, errs.Wrap(errs.Internal, err, "blobstore")
	}
	if !fi.ModTime().Before(before) {
		return false, nil
	}
	doomed := filepath.Join(s.root, "tmp", "gc-"+filepath.Base(path))
	if err := os.Rename(path, doomed); err != nil {
		if errors.Is(err, fs.ErrNotExist) {
			return false, nil
		}
		return false, errs.Wrap(errs.Internal, err, "blobstore")
	}
	if fi, err = os.Stat(doomed); err == nil && !fi.ModTime().Before(before) {
		// Touched on the way: back it goes (over an identical upload, if one came).
		if err := os.Rename(doomed, path); err != nil {
			return false, errs.Wrap(errs.Internal, err, "blobstore")
		}
		return false, nil
	}
	if err := os.Remove(doomed); err != nil {
		return false, errs.Wrap(errs.Internal, err, "blobstore")
	}
	return true, nil
}
