// Package blobstore is a content-addressed store of immutable blobs, kept in a folder
// (file://, the embedded default) or in an S3-compatible object store (s3://; s3.go).
//
// A blob is named by its digest, "sha256:" and 64 lowercase hex digits. Its bytes are
// hashed on the way in and checked against the declared size and digest before it
// becomes visible under its digest, so a blob is either absent or complete. In a folder
// it lives at root/sha256/<first two hex digits>/<hex> (file.go), written to root/tmp
// first and renamed into place; in an object store under the key sha256/<two>/<hex>.
//
// A disk or an object store can still damage a blob after it was stored (or an operator
// replace one), so every read is checked too: Open's reader hashes what it reads and ends
// in an errs.DataLoss error instead of io.EOF when the content does not match the
// digest, and Verify hashes a blob whole before anything of it is served. Checking on
// read rather than by a periodic scrub means corrupt bytes are never used or served,
// however recently they were damaged; the cost is one hash per read (SHA-256 runs at
// about 1.5 GB/s a core, against a network or disk that is slower).
package blobstore

import (
	"context"
	"errors"
	"fmt"
	"hash"
	"io"
	"strings"
	"time"

	"photonfarm/contract/rules"
	"photonfarm/coordinator/errs"
)

// DefaultMaxSize is the default size limit of one blob: the contract's max_blob_bytes.
var DefaultMaxSize = int64(rules.RPC.GetMaxBlobBytes())

// Info describes a stored blob.
type Info struct {
	Digest string
	Size   int64
}

// backend is where a Store keeps the bytes: a folder (file.go) or an object store
// (s3.go). The Store checks digests, sizes and limits; a backend only stores, and reports
// its failures as *errs.Error (NotFound for an absent blob; what the caller can do about
// anything else).
type backend interface {
	// size is the stored size of a valid digest's blob, or errs.NotFound.
	size(ctx context.Context, digest string) (int64, error)
	// open reads the length bytes from offset of a blob that size found at least
	// offset+length bytes long; the reader's errors are *errs.Error (a file that shrank is
	// damage; a body cut short, a failed connection).
	open(ctx context.Context, digest string, offset, length int64) (io.ReadCloser, error)
	// create starts a blob whose digest is known (declared, checked before commit) or
	// not ("").
	create(ctx context.Context, declared string) (sink, error)
	walk(ctx context.Context, fn func(Entry) error) error
	// touch marks a blob in use now; an absent one is not an error.
	touch(ctx context.Context, digest string) error
	deleteUnused(ctx context.Context, digest string, before time.Time) (bool, error)
	Close() error
	// String names the backend in messages, without credentials.
	String() string
}

// sink receives a blob's bytes for a backend: commit makes them the blob of digest
// (which the Store has checked), abort drops them; after either, abort does nothing.
type sink interface {
	io.Writer
	commit(digest string) error
	abort()
}

// Store is a blob store. Create it with New (a folder) or Open (a URL).
type Store struct {
	b       backend
	maxSize int64
}

func newStore(b backend, maxSize int64) *Store {
	if maxSize <= 0 {
		maxSize = DefaultMaxSize
	}
	return &Store{b: b, maxSize: maxSize}
}

// New opens (creating if needed) a blob store in the folder root. maxSize <= 0 selects
// DefaultMaxSize.
func New(root string, maxSize int64) (*Store, error) {
	b, err := newFileBackend(root)
	if err != nil {
		return nil, err
	}
	return newStore(b, maxSize), nil
}

// MaxSize is the largest blob the store accepts.
func (s *Store) MaxSize() int64 { return s.maxSize }

// String names where the blobs are, for logs: a folder or a bucket, never credentials.
func (s *Store) String() string { return s.b.String() }

// Close releases the backend's connections.
func (s *Store) Close() error { return s.b.Close() }

func checkDigest(field, d string) error {
	if !rules.ValidDigest(d) {
		return errs.Field(field, "must be \"sha256:\" followed by 64 lowercase hex digits, got %q", d)
	}
	return nil
}

func notFound(digest string) error {
	return &errs.Error{Kind: errs.NotFound, Field: "digest", Message: "no blob " + digest}
}

// Stat returns errs.NotFound if the blob does not exist.
func (s *Store) Stat(ctx context.Context, digest string) (Info, error) {
	if err := checkDigest("digest", digest); err != nil {
		return Info{}, err
	}
	n, err := s.b.size(ctx, digest)
	if err != nil {
		return Info{}, err
	}
	return Info{Digest: digest, Size: n}, nil
}

// Open opens a blob for reading; the caller closes it. The reader checks the content as
// it goes: at the end of a blob whose bytes do not match its digest it returns an
// errs.DataLoss error (Corrupt) instead of io.EOF, so that a caller reading to the end
// never takes damaged bytes for the blob. A caller that stops early has checked nothing.
func (s *Store) Open(ctx context.Context, digest string) (io.ReadCloser, Info, error) {
	info, err := s.Stat(ctx, digest)
	if err != nil {
		return nil, Info{}, err
	}
	r, err := s.b.open(ctx, digest, 0, info.Size)
	if err != nil {
		return nil, Info{}, err
	}
	return &checkedReader{r: r, h: rules.NewDigestHash(), digest: digest}, info, nil
}

// OpenRange opens the bytes [offset, offset+length) of a blob for reading; length 0, or
// one past the end, reads to the end. Unlike Open's, the reader cannot check the content
// (that takes the whole blob): a caller that assembles a blob from ranges checks the whole
// against the digest itself, and Verify tells damage in the store from a fault on the way.
// An offset past the end is errs.OutOfRange; a blob that turns out shorter than the range
// while read is errs.DataLoss.
func (s *Store) OpenRange(ctx context.Context, digest string, offset, length int64) (io.ReadCloser, Info, error) {
	info, err := s.Stat(ctx, digest)
	if err != nil {
		return nil, Info{}, err
	}
	if offset < 0 || offset > info.Size {
		return nil, Info{}, &errs.Error{Kind: errs.OutOfRange, Field: "offset",
			Message: fmt.Sprintf("%d is past the end of blob %s of %d bytes", offset, digest, info.Size)}
	}
	if length <= 0 || length > info.Size-offset {
		length = info.Size - offset
	}
	if length == 0 {
		return io.NopCloser(strings.NewReader("")), info, nil
	}
	r, err := s.b.open(ctx, digest, offset, length)
	if err != nil {
		return nil, Info{}, err
	}
	return r, info, nil
}

// Verify reads the blob whole and checks it against its digest: errs.NotFound if it is
// absent, errs.DataLoss if its content does not match (Corrupt). It stops with ctx's error
// when ctx ends.
func (s *Store) Verify(ctx context.Context, digest string) (Info, error) {
	r, info, err := s.Open(ctx, digest)
	if err != nil {
		return Info{}, err
	}
	defer r.Close()
	// No bigger than the blob (plus the byte that meets its end): a 1 MiB buffer zeroed
	// for every tiny tile's GetBlobInfo was most of a loaded coordinator's CPU
	// (bench/cmd/loadsim).
	buf := make([]byte, min(info.Size+1, 1<<20))
	for {
		if err := ctx.Err(); err != nil {
			return Info{}, err
		}
		_, err := r.Read(buf)
		if errors.Is(err, io.EOF) {
			return info, nil
		}
		if err != nil {
			return Info{}, err
		}
	}
}

// ReadAll reads a blob opened with Open whole: its size bytes (Info.Size), then its end,
// where the reader checks the content, so that damage is an error here.
func ReadAll(r io.Reader, size int64) ([]byte, error) {
	data := make([]byte, size)
	if _, err := io.ReadFull(r, data); err != nil {
		if errors.Is(err, io.ErrUnexpectedEOF) || errors.Is(err, io.EOF) {
			err = errs.E(errs.DataLoss, "blob shrank to fewer than its %d bytes while read", size)
		}
		return nil, err
	}
	n, err := r.Read(make([]byte, 1))
	if n > 0 {
		err = errs.E(errs.DataLoss, "blob grew past its %d bytes while read", size)
	}
	if !errors.Is(err, io.EOF) {
		return nil, err
	}
	return data, nil
}

// Corrupt is the error of a blob whose stored content does not match its digest.
func Corrupt(digest, got string, size int64) error {
	return &errs.Error{Kind: errs.DataLoss, Message: fmt.Sprintf(
		"blob %s is damaged in the coordinator's blob store: its %d bytes have digest %s", digest, size, got)}
}

// LostError is the error of a blob a reader needs that the store cannot give: missing
// (errs.NotFound) or damaged (errs.DataLoss). What says what the blob holds, for people:
// "the scene", "tile x 32 y 64 of round 1".
type LostError struct {
	What, Digest string
	Err          error
}

func (e *LostError) Error() string {
	if errs.Is(e.Err, errs.NotFound) {
		return fmt.Sprintf("%s: blob %s is not in the coordinator's blob store", e.What, e.Digest)
	}
	var d *errs.Error
	if errors.As(e.Err, &d) && d.Kind == errs.DataLoss {
		return e.What + ": " + d.Message
	}
	return e.What + ": " + e.Err.Error()
}

func (e *LostError) Unwrap() error { return e.Err }

// Lost makes err, the store's answer about the blob digest holding what, a *LostError if
// it says the blob is missing or damaged; other errors (nil included) pass unchanged.
func Lost(what, digest string, err error) error {
	if errs.Is(err, errs.NotFound) || errs.Is(err, errs.DataLoss) {
		return &LostError{What: what, Digest: digest, Err: err}
	}
	return err
}

// checkedReader reads a blob from its backend and, at its end, checks what it read
// against the digest.
type checkedReader struct {
	r      io.ReadCloser
	h      hash.Hash
	n      int64
	digest string
	err    error // sticky: the end's verdict, or a read error
}

func (r *checkedReader) Read(p []byte) (int, error) {
	if r.err != nil {
		return 0, r.err
	}
	n, err := r.r.Read(p)
	r.h.Write(p[:n])
	r.n += int64(n)
	switch {
	case errors.Is(err, io.EOF):
		if got := rules.DigestSum(r.h); got != r.digest {
			err = Corrupt(r.digest, got, r.n)
		}
		r.err = err
	case err != nil:
		if e := (*errs.Error)(nil); !errors.As(err, &e) {
			err = errs.Wrap(errs.Internal, err, "blobstore: read "+r.digest)
		}
		r.err = err
	}
	return n, err
}

func (r *checkedReader) Close() error { return r.r.Close() }

// Put stores everything r yields. size and digest, when not negative and not empty, are
// what the content must match.
func (s *Store) Put(ctx context.Context, r io.Reader, size int64, digest string) (Info, error) {
	w, err := s.Create(ctx, size, digest)
	if err != nil {
		return Info{}, err
	}
	defer w.Abort()
	if _, err := io.Copy(w, r); err != nil {
		return Info{}, err
	}
	return w.Commit()
}

// Writer receives a blob's bytes. Call Commit to store it or Abort to drop it (Abort after
// Commit does nothing, so `defer w.Abort()` is safe).
type Writer struct {
	s      *Store
	sink   sink
	h      hash.Hash
	n      int64
	size   int64
	digest string
	done   bool
}

// Create starts a blob of the declared size (negative: unknown) and, if not empty,
// digest. ctx bounds the whole upload: a Writer whose ctx ends stores nothing.
func (s *Store) Create(ctx context.Context, size int64, digest string) (*Writer, error) {
	if digest != "" {
		if err := checkDigest("digest", digest); err != nil {
			return nil, err
		}
	}
	if size > s.maxSize {
		return nil, &errs.Error{Kind: errs.ResourceExhausted, Field: "size_bytes",
			Message: fmt.Sprintf("blob of %d bytes exceeds the limit of %d bytes", size, s.maxSize)}
	}
	k, err := s.b.create(ctx, digest)
	if err != nil {
		return nil, err
	}
	return &Writer{s: s, sink: k, h: rules.NewDigestHash(), size: size, digest: digest}, nil
}

// Write appends p, refusing to grow past the declared size or the store's limit.
func (w *Writer) Write(p []byte) (int, error) {
	if w.done {
		return 0, errs.E(errs.Internal, "blobstore: write after commit or abort")
	}
	n := w.n + int64(len(p))
	if w.size >= 0 && n > w.size {
		return 0, &errs.Error{Kind: errs.InvalidArgument, Field: "size_bytes",
			Message: fmt.Sprintf("received more than the declared %d bytes", w.size)}
	}
	if n > w.s.maxSize {
		return 0, &errs.Error{Kind: errs.ResourceExhausted, Field: "size_bytes",
			Message: fmt.Sprintf("blob exceeds the limit of %d bytes", w.s.maxSize)}
	}
	if _, err := w.sink.Write(p); err != nil {
		return 0, err
	}
	w.h.Write(p)
	w.n = n
	return len(p), nil
}

// Commit verifies the size and digest and makes the blob visible under its digest.
func (w *Writer) Commit() (Info, error) {
	if w.done {
		return Info{}, errs.E(errs.Internal, "blobstore: commit after commit or abort")
	}
	defer w.Abort()
	if w.size >= 0 && w.n != w.size {
		return Info{}, &errs.Error{Kind: errs.InvalidArgument, Field: "size_bytes",
			Message: fmt.Sprintf("declared %d bytes, received %d", w.size, w.n)}
	}
	got := rules.DigestSum(w.h)
	if w.digest != "" && got != w.digest {
		return Info{}, &errs.Error{Kind: errs.InvalidArgument, Field: "digest",
			Message: fmt.Sprintf("content has digest %s, not the declared %s", got, w.digest)}
	}
	if err := w.sink.commit(got); err != nil {
		return Info{}, err
	}
	return Info{Digest: got, Size: w.n}, nil
}

// Abort drops the partial blob.
func (w *Writer) Abort() {
	if w.done {
		return
	}
	w.done = true
	w.sink.abort()
}

// probeDigest names a blob nobody stores (the digest of no known content): asking for its
// size reaches the backend and answers NotFound when the backend is up.
const probeDigest = "sha256:0000000000000000000000000000000000000000000000000000000000000000"

// Ping reports whether the backend answers, for the coordinator's health service: a
// size lookup of a blob that does not exist, which succeeds as NotFound.
func (s *Store) Ping(ctx context.Context) error {
	_, err := s.b.size(ctx, probeDigest)
	if err == nil || errs.Is(err, errs.NotFound) {
		return nil
	}
	return err
}
