package blobstore_test

import (
	"context"
	"errors"
	"io"
	"os"
	"path/filepath"
	"testing"

	"gocloud.dev/blob"
	_ "gocloud.dev/blob/s3blob"

	"photonfarm/coordinator/blobstore"
	"photonfarm/coordinator/blobstore/s3test"
)

func TestMain(m *testing.M) { s3test.Main(m) }

// A backend under test: a new, empty store, and access to its stored bytes behind the
// store's back, as a damaged disk or an operator would have.
type backend struct {
	name string
	open func(t *testing.T, maxSize int64) (*blobstore.Store, raw)
}

// raw reads and writes what a store holds for a digest, and lists what uploads and
// collections left behind.
type raw interface {
	read(t *testing.T, digest string) []byte
	write(t *testing.T, digest string, b []byte)
	leftovers(t *testing.T) []string
}

// backends is every backend the conformance suite runs on: a folder, and a real
// S3-compatible server (SeaweedFS) shared by the package's tests.
var backends = []backend{
	{"file", func(t *testing.T, maxSize int64) (*blobstore.Store, raw) {
		root := t.TempDir()
		s, err := blobstore.New(root, maxSize)
		if err != nil {
			t.Fatal(err)
		}
		return s, folder(root)
	}},
	{"s3", func(t *testing.T, maxSize int64) (*blobstore.Store, raw) {
		u := s3test.Shared(t).TestURL(t)
		s, err := blobstore.Open(context.Background(), u, maxSize)
		if err != nil {
			t.Fatal(err)
		}
		t.Cleanup(func() { s.Close() })
		b, err := blob.OpenBucket(context.Background(), u)
		if err != nil {
			t.Fatal(err)
		}
		t.Cleanup(func() { b.Close() })
		return s, bucket{b}
	}},
}

// forEachBackend runs test as a subtest on every backend.
func forEachBackend(t *testing.T, test func(t *testing.T, open func(maxSize int64) (*blobstore.Store, raw))) {
	for _, b := range backends {
		t.Run(b.name, func(t *testing.T) {
			t.Parallel()
			test(t, func(maxSize int64) (*blobstore.Store, raw) { return b.open(t, maxSize) })
		})
	}
}

type folder string

func (f folder) read(t *testing.T, digest string) []byte {
	t.Helper()
	b, err := os.ReadFile(blobstore.PathIn(string(f), digest))
	if err != nil {
		t.Fatal(err)
	}
	return b
}

func (f folder) write(t *testing.T, digest string, b []byte) {
	t.Helper()
	if err := os.WriteFile(blobstore.PathIn(string(f), digest), b, 0o644); err != nil {
		t.Fatal(err)
	}
}

func (f folder) leftovers(t *testing.T) []string {
	t.Helper()
	ents, err := os.ReadDir(filepath.Join(string(f), "tmp"))
	if err != nil {
		t.Fatal(err)
	}
	var names []string
	for _, e := range ents {
		names = append(names, e.Name())
	}
	return names
}

type bucket struct{ b *blob.Bucket }

func (k bucket) read(t *testing.T, digest string) []byte {
	t.Helper()
	b, err := k.b.ReadAll(context.Background(), blobstore.ObjectKey(digest))
	if err != nil {
		t.Fatal(err)
	}
	return b
}

func (k bucket) write(t *testing.T, digest string, b []byte) {
	t.Helper()
	if err := k.b.WriteAll(context.Background(), blobstore.ObjectKey(digest), b, nil); err != nil {
		t.Fatal(err)
	}
}

// leftovers are the objects of unfinished uploads (tmp/) and collections (gc/).
func (k bucket) leftovers(t *testing.T) []string {
	t.Helper()
	var names []string
	for _, prefix := range []string{"tmp/", "gc/"} {
		it := k.b.List(&blob.ListOptions{Prefix: prefix})
		for {
			o, err := it.Next(context.Background())
			if errors.Is(err, io.EOF) {
				break
			}
			if err != nil {
				t.Fatal(err)
			}
			names = append(names, o.Key)
		}
	}
	return names
}
