package blobstore

import (
	"context"
	"errors"
	"fmt"
	"io"
	"io/fs"
	"os"
	"path/filepath"
	"syscall"
	"time"

	"photonfarm/contract/rules"
	"photonfarm/coordinator/errs"
)

// fileBackend keeps blobs in a folder: root/sha256/ab/<hex>, written to root/tmp first
// and renamed into place. A blob's modification time is when it was last written or
// touched.
type fileBackend struct{ root string }

func newFileBackend(root string) (*fileBackend, error) {
	for _, d := range []string{filepath.Join(root, "sha256"), filepath.Join(root, "tmp")} {
		if err := os.MkdirAll(d, 0o755); err != nil {
			return nil, fmt.Errorf("blobstore: %w", err)
		}
	}
	return &fileBackend{root: root}, nil
}

func (b *fileBackend) String() string { return "file://" + b.root }

func (b *fileBackend) Close() error { return nil }

func (b *fileBackend) path(digest string) string { return PathIn(b.root, digest) }

// PathIn is where the blob of a valid digest lives in a folder store rooted at root: for
// operators looking for a blob, and tests that damage one.
func PathIn(root, digest string) string {
	hexd := digest[len("sha256:"):]
	return filepath.Join(root, "sha256", hexd[:2], hexd)
}

func (b *fileBackend) size(ctx context.Context, digest string) (int64, error) {
	fi, err := os.Stat(b.path(digest))
	if errors.Is(err, fs.ErrNotExist) {
		return 0, notFound(digest)
	}
	if err != nil {
		return 0, errs.Wrap(errs.Internal, err, "blobstore")
	}
	return fi.Size(), nil
}

func (b *fileBackend) open(ctx context.Context, digest string, offset, length int64) (io.ReadCloser, error) {
	f, err := os.Open(b.path(digest))
	if errors.Is(err, fs.ErrNotExist) {
		return nil, notFound(digest)
	}
	if err != nil {
		return nil, errs.Wrap(errs.Internal, err, "blobstore")
	}
	return &fileRange{f: f, r: io.NewSectionReader(f, offset, length), digest: digest, left: length}, nil
}

// fileRange reads a range of a blob's file: a file that ends before the range does has
// shrunk since it was stored, which is damage.
type fileRange struct {
	f      *os.File
	r      io.Reader
	digest string
	left   int64
}

func (r *fileRange) Read(p []byte) (int, error) {
	n, err := r.r.Read(p)
	r.left -= int64(n)
	switch {
	case errors.Is(err, io.EOF) && r.left > 0:
		err = errs.E(errs.DataLoss, "blob %s is damaged in the coordinator's blob store: its file ends %d bytes early", r.digest, r.left)
	case err != nil && !errors.Is(err, io.EOF):
		err = errs.Wrap(errs.Internal, err, "blobstore")
	}
	return n, err
}

func (r *fileRange) Close() error { return r.f.Close() }

// fileSink is a blob being written to a temporary file.
type fileSink struct {
	b    *fileBackend
	f    *os.File
	done bool
}

func (b *fileBackend) create(context.Context, string) (sink, error) {
	f, err := os.CreateTemp(filepath.Join(b.root, "tmp"), "upload-*")
	if err != nil {
		return nil, writeError(err)
	}
	return &fileSink{b: b, f: f}, nil
}

func (k *fileSink) Write(p []byte) (int, error) {
	n, err := k.f.Write(p)
	if err != nil {
		return n, writeError(err)
	}
	return n, nil
}

// commit syncs the file and renames it to its content address.
func (k *fileSink) commit(digest string) error {
	if err := k.f.Sync(); err != nil {
		return writeError(err)
	}
	if err := k.f.Close(); err != nil {
		return writeError(err)
	}
	dst := k.b.path(digest)
	if err := os.MkdirAll(filepath.Dir(dst), 0o755); err != nil {
		return writeError(err)
	}
	// Identical content may already be there; renaming over it is harmless.
	if err := os.Rename(k.f.Name(), dst); err != nil {
		return writeError(err)
	}
	return nil
}

func (k *fileSink) abort() {
	if k.done {
		return
	}
	k.done = true
	k.f.Close()
	os.Remove(k.f.Name()) // fails harmlessly after a successful rename
}

// writeError is err from writing a blob to disk: resource exhaustion when the disk or
// the quota is full (IsDiskFull), so that neither the uploader nor the builder is blamed
// for it (a worker pauses and retries; the task's attempts still end a job that never
// gets the space), else internal.
func writeError(err error) error {
	if IsDiskFull(err) {
		return errs.Wrap(errs.ResourceExhausted, err, "blobstore: the coordinator's disk is full")
	}
	return errs.Wrap(errs.Internal, err, "blobstore")
}

// IsDiskFull reports whether err comes from a full disk or quota (ENOSPC, EDQUOT).
func IsDiskFull(err error) bool {
	return errors.Is(err, syscall.ENOSPC) || errors.Is(err, syscall.EDQUOT)
}

func (b *fileBackend) walk(ctx context.Context, fn func(Entry) error) error {
	return filepath.WalkDir(filepath.Join(b.root, "sha256"), func(path string, d fs.DirEntry, err error) error {
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

func (b *fileBackend) touch(ctx context.Context, digest string) error {
	now := time.Now()
	if err := os.Chtimes(b.path(digest), now, now); err != nil && !errors.Is(err, fs.ErrNotExist) {
		return errs.Wrap(errs.Internal, err, "blobstore")
	}
	return nil
}

// deleteUnused first moves the blob out of reach (root/tmp), and checks its time again
// there: a blob touched meanwhile is put back.
func (b *fileBackend) deleteUnused(ctx context.Context, digest string, before time.Time) (bool, error) {
	path := b.path(digest)
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
	doomed := filepath.Join(b.root, "tmp", "gc-"+filepath.Base(path))
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
