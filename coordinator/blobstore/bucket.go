package blobstore

import (
	"context"
	"crypto/rand"
	"encoding/hex"
	"errors"
	"fmt"
	"io"
	"strings"
	"time"

	"gocloud.dev/blob"
	"gocloud.dev/gcerrors"

	"photonfarm/contract/rules"
	"photonfarm/coordinator/errs"
)

// bucketBackend keeps blobs in an object store bucket (gocloud.dev/blob; s3:// in
// url.go): the blob of sha256:<hex> under the key sha256/<hex[:2]>/<hex>. Object stores
// write an object whole or not at all, so an upload whose digest is declared goes straight
// to its key and is aborted (never written) if the content turns out different; one whose
// digest is only known at the end goes to tmp/ and is copied into place in the store.
//
// Objects cannot be renamed nor their times changed, so the collector's protocol
// (gc.go) is kept with two more kinds of object: Touch writes touched/<hex>, an empty
// object whose metadata holds the time of the touch to the nanosecond (object times are
// whole seconds), and DeleteUnused copies a blob to gc/<hex> before deleting it, so that
// one touched meanwhile can be put back.
//
// Every call on the store runs under a stall guard: a call that gets no answer for
// stall (the server stopped, frozen or cut off) ends in errs.Unavailable naming the store,
// never a hang, however long a large transfer takes as a whole.
type bucketBackend struct {
	b     *blob.Bucket
	name  string // for messages: s3://BUCKET/PREFIX at ENDPOINT, no credentials (url.go)
	stall time.Duration
}

// touchedKey is the metadata key of a touch marker's time.
const touchedKey = "touched"

// ObjectKey is the key of a valid digest's blob in an object store (under the URL's
// prefix): for operators looking for a blob, and tests that damage one.
func ObjectKey(digest string) string {
	h := digest[len("sha256:"):]
	return "sha256/" + h[:2] + "/" + h
}

func (b *bucketBackend) String() string { return b.name }

func (b *bucketBackend) Close() error { return b.b.Close() }

// errStalled is the cause of a call the stall guard ended.
var errStalled = errors.New("stalled")

// stallGuard cancels the context of a call on the store when one step of it (the
// request, a read, a write, the final upload) takes longer than limit.
type stallGuard struct {
	limit  time.Duration
	timer  *time.Timer
	cancel context.CancelCauseFunc
}

func newStallGuard(ctx context.Context, limit time.Duration) (context.Context, *stallGuard) {
	ctx, cancel := context.WithCancelCause(ctx)
	g := &stallGuard{limit: limit, cancel: cancel}
	g.timer = time.AfterFunc(limit, func() { cancel(errStalled) })
	g.timer.Stop()
	return ctx, g
}

func (g *stallGuard) begin() { g.timer.Reset(g.limit) }
func (g *stallGuard) end()   { g.timer.Stop() }
func (g *stallGuard) release() {
	g.timer.Stop()
	g.cancel(context.Canceled)
}

// fail classifies err from op on key: NotFound for a missing object (of digest, when the
// key is a blob's), the caller's own ctx error when the caller gave up, else Unavailable
// naming the store and saying whether it stalled.
func (b *bucketBackend) fail(caller, guarded context.Context, op, key string, err error) error {
	switch {
	case err == nil:
		return nil
	case gcerrors.Code(err) == gcerrors.NotFound:
		if d, ok := digestOfKey(key); ok {
			return notFound(d)
		}
		return &errs.Error{Kind: errs.NotFound, Message: fmt.Sprintf("object store %s: no object %s", b.name, key)}
	case caller.Err() != nil:
		return caller.Err()
	case errors.Is(context.Cause(guarded), errStalled):
		return errs.E(errs.Unavailable, "object store %s: %s %s got no answer for %s: %v", b.name, op, key, b.stall, err)
	}
	// The cause is kept as text only: an io.ErrUnexpectedEOF in the chain would make a
	// reader of the blob take a cut connection for a truncated file.
	return errs.E(errs.Unavailable, "object store %s: %s %s: %v", b.name, op, key, err)
}

func digestOfKey(key string) (string, bool) {
	d := "sha256:" + key[strings.LastIndexByte(key, '/')+1:]
	return d, strings.HasPrefix(key, "sha256/") && rules.ValidDigest(d)
}

// do runs one call on the store under a stall guard.
func (b *bucketBackend) do(ctx context.Context, op, key string, f func(ctx context.Context) error) error {
	gctx, g := newStallGuard(ctx, b.stall)
	defer g.release()
	g.begin()
	return b.fail(ctx, gctx, op, key, f(gctx))
}

func (b *bucketBackend) attributes(ctx context.Context, key string) (*blob.Attributes, error) {
	var a *blob.Attributes
	err := b.do(ctx, "stat", key, func(ctx context.Context) (err error) {
		a, err = b.b.Attributes(ctx, key)
		return err
	})
	return a, err
}

func (b *bucketBackend) size(ctx context.Context, digest string) (int64, error) {
	a, err := b.attributes(ctx, ObjectKey(digest))
	if err != nil {
		return 0, err
	}
	return a.Size, nil
}

// bucketReader reads an object, each Read under the stall guard.
type bucketReader struct {
	b       *bucketBackend
	caller  context.Context
	guarded context.Context
	g       *stallGuard
	r       *blob.Reader
	key     string
	n       int64 // bytes read so far
	size    int64 // of the range read, within the object's size from the stat before
}

func (b *bucketBackend) open(ctx context.Context, digest string, offset, length int64) (io.ReadCloser, error) {
	key := ObjectKey(digest)
	gctx, g := newStallGuard(ctx, b.stall)
	g.begin()
	ask := length
	if ask == 0 {
		ask = -1 // an empty blob read whole: S3 refuses an empty range, not the rest of an object
	}
	r, err := b.b.NewRangeReader(gctx, key, offset, ask, nil)
	g.end()
	if err != nil {
		err = b.fail(ctx, gctx, "read", key, err)
		g.release()
		return nil, err
	}
	return &bucketReader{b: b, caller: ctx, guarded: gctx, g: g, r: r, key: key, size: length}, nil
}

// Read reads on; a body that ends before the object's size is a connection that
// ended (the server stopped mid-read): unavailable, never the end of a blob, which the
// checked reader would take for damage and a parser for a malformed file.
func (r *bucketReader) Read(p []byte) (int, error) {
	r.g.begin()
	n, err := r.r.Read(p)
	r.g.end()
	r.n += int64(n)
	switch {
	case errors.Is(err, io.EOF) && r.n < r.size:
		err = errs.E(errs.Unavailable, "object store %s: read %s: the connection ended after %d of its %d bytes", r.b.name, r.key, r.n, r.size)
	case err != nil && !errors.Is(err, io.EOF):
		err = r.b.fail(r.caller, r.guarded, "read", r.key, err)
	}
	return n, err
}

func (r *bucketReader) Close() error {
	defer r.g.release()
	return r.r.Close()
}

// bucketSink uploads a blob: to its key when the digest was declared, else to tmp/.
type bucketSink struct {
	b       *bucketBackend
	caller  context.Context
	guarded context.Context
	g       *stallGuard
	w       *blob.Writer
	key     string
	direct  bool // key is the blob's own
	closed  bool // w is closed: the object at key exists
	done    bool
}

func (b *bucketBackend) create(ctx context.Context, declared string) (sink, error) {
	k := &bucketSink{b: b, caller: ctx, direct: declared != ""}
	if k.direct {
		k.key = ObjectKey(declared)
	} else {
		var id [16]byte
		rand.Read(id[:])
		k.key = "tmp/upload-" + hex.EncodeToString(id[:])
	}
	k.guarded, k.g = newStallGuard(ctx, b.stall)
	w, err := b.b.NewWriter(k.guarded, k.key, &blob.WriterOptions{ContentType: "application/octet-stream"})
	if err != nil {
		err = b.fail(ctx, k.guarded, "write", k.key, err)
		k.g.release()
		return nil, err
	}
	k.w = w
	return k, nil
}

func (k *bucketSink) Write(p []byte) (int, error) {
	k.g.begin()
	n, err := k.w.Write(p)
	k.g.end()
	return n, k.b.fail(k.caller, k.guarded, "write", k.key, err)
}

func (k *bucketSink) commit(digest string) error {
	k.g.begin()
	err := k.w.Close()
	k.g.end()
	k.closed = true
	if err != nil {
		return k.b.fail(k.caller, k.guarded, "write", k.key, err)
	}
	if k.direct {
		return nil
	}
	dst := ObjectKey(digest)
	if err := k.b.do(k.caller, "copy to "+dst, k.key, func(ctx context.Context) error {
		return k.b.b.Copy(ctx, dst, k.key, nil)
	}); err != nil {
		return err
	}
	k.removeTemp()
	k.done = true
	k.g.release()
	return nil
}

// removeTemp deletes the upload's temporary object, on a context of its own: the
// caller's may have ended, and a failure only leaves an object under tmp/.
func (k *bucketSink) removeTemp() {
	ctx, cancel := context.WithTimeout(context.Background(), k.b.stall)
	defer cancel()
	_ = k.b.b.Delete(ctx, k.key)
}

func (k *bucketSink) abort() {
	if k.done {
		return
	}
	k.done = true
	k.g.release() // cancelling the writer's context before Close aborts the upload
	if !k.closed {
		_ = k.w.Close()
	} else if !k.direct {
		go k.removeTemp() // not waited for: the store may be the reason of the abort
	}
}

// touch writes the blob's touch marker, then checks the blob is there (the order the
// collector's protocol needs); a marker of an absent blob is deleted again.
func (b *bucketBackend) touch(ctx context.Context, digest string) error {
	key := "touched/" + digest[len("sha256:"):]
	now := time.Now().UTC().Format(time.RFC3339Nano)
	opts := &blob.WriterOptions{ContentType: "application/octet-stream", Metadata: map[string]string{touchedKey: now}}
	if err := b.do(ctx, "write", key, func(ctx context.Context) error { return b.b.WriteAll(ctx, key, nil, opts) }); err != nil {
		return err
	}
	_, err := b.size(ctx, digest)
	if errs.Is(err, errs.NotFound) {
		return b.do(ctx, "delete", key, func(ctx context.Context) error { return b.b.Delete(ctx, key) })
	}
	return err
}

// objectTime is when an object was last written: object stores give whole seconds, so
// the end of that second, keeping a blob a little longer rather than shorter.
func objectTime(t time.Time) time.Time { return t.Truncate(time.Second).Add(time.Second) }

// touchedAt is when the blob of hex was last touched (zero if never).
func (b *bucketBackend) touchedAt(ctx context.Context, hexd string) (time.Time, error) {
	a, err := b.attributes(ctx, "touched/"+hexd)
	if errs.Is(err, errs.NotFound) {
		return time.Time{}, nil
	}
	if err != nil {
		return time.Time{}, err
	}
	if t, err := time.Parse(time.RFC3339Nano, a.Metadata[touchedKey]); err == nil {
		return t, nil
	}
	return objectTime(a.ModTime), nil
}

// deleteUnused copies the blob to gc/, deletes it, and checks its touch marker again:
// a blob touched meanwhile is copied back.
func (b *bucketBackend) deleteUnused(ctx context.Context, digest string, before time.Time) (bool, error) {
	hexd := digest[len("sha256:"):]
	key, doomed, marker := ObjectKey(digest), "gc/"+hexd, "touched/"+hexd
	a, err := b.attributes(ctx, key)
	if errs.Is(err, errs.NotFound) {
		return false, nil
	}
	if err != nil {
		return false, err
	}
	touched, err := b.touchedAt(ctx, hexd)
	if err != nil {
		return false, err
	}
	if !objectTime(a.ModTime).Before(before) || !touched.Before(before) {
		return false, nil
	}
	copyTo := func(dst, src string) error {
		return b.do(ctx, "copy to "+dst, src, func(ctx context.Context) error { return b.b.Copy(ctx, dst, src, nil) })
	}
	del := func(key string) error {
		err := b.do(ctx, "delete", key, func(ctx context.Context) error { return b.b.Delete(ctx, key) })
		if errs.Is(err, errs.NotFound) {
			return nil
		}
		return err
	}
	if err := copyTo(doomed, key); errs.Is(err, errs.NotFound) {
		return false, nil
	} else if err != nil {
		return false, err
	}
	if err := del(key); err != nil {
		return false, err
	}
	if touched, err = b.touchedAt(ctx, hexd); err != nil || !touched.Before(before) {
		// Touched on the way (or unknown): back it goes, over an identical upload if one came.
		if err := copyTo(key, doomed); err != nil {
			return false, err
		}
		return false, del(doomed)
	}
	if err := del(doomed); err != nil {
		return false, err
	}
	return true, del(marker)
}

// walk lists the touch markers, then the blobs, each with the later of its write and
// its touch.
func (b *bucketBackend) walk(ctx context.Context, fn func(Entry) error) error {
	touched := map[string]time.Time{}
	if err := b.list(ctx, "touched/", func(o *blob.ListObject) error {
		touched[o.Key[len("touched/"):]] = objectTime(o.ModTime)
		return nil
	}); err != nil {
		return err
	}
	return b.list(ctx, "sha256/", func(o *blob.ListObject) error {
		d, ok := digestOfKey(o.Key)
		if !ok {
			return nil
		}
		t := objectTime(o.ModTime)
		if m := touched[d[len("sha256:"):]]; m.After(t) {
			t = m
		}
		return fn(Entry{Digest: d, Size: o.Size, ModTime: t})
	})
}

// list calls fn with every object under prefix, a page at a time.
func (b *bucketBackend) list(ctx context.Context, prefix string, fn func(*blob.ListObject) error) error {
	token := blob.FirstPageToken
	for {
		var page []*blob.ListObject
		err := b.do(ctx, "list", prefix, func(ctx context.Context) (err error) {
			page, token, err = b.b.ListPage(ctx, token, 1000, &blob.ListOptions{Prefix: prefix})
			return err
		})
		if err != nil {
			return err
		}
		for _, o := range page {
			if err := fn(o); err != nil {
				return err
			}
		}
		if len(token) == 0 {
			return nil
		}
	}
}
