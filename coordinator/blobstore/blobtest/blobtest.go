// Package blobtest makes blob stores for tests of what reads and collects blobs.
package blobtest

import (
	"context"
	"os"
	"path/filepath"
	"strings"
	"testing"
	"time"

	"photonfarm/coordinator/blobstore"
)

// Store is a blob store in a test's temporary folder.
type Store struct {
	*blobstore.Store
	t    testing.TB
	root string
}

// New returns an empty Store.
func New(t testing.TB) *Store {
	t.Helper()
	root := t.TempDir()
	s, err := blobstore.New(root, 0)
	if err != nil {
		t.Fatal(err)
	}
	return &Store{Store: s, t: t, root: root}
}

// Put stores content and returns its digest.
func (s *Store) Put(content string) string {
	s.t.Helper()
	info, err := s.Store.Put(context.Background(), strings.NewReader(content), int64(len(content)), "")
	if err != nil {
		s.t.Fatal(err)
	}
	return info.Digest
}

// Age makes the blobs look last written or touched at at.
func (s *Store) Age(at time.Time, digests ...string) {
	s.t.Helper()
	for _, d := range digests {
		hex := strings.TrimPrefix(d, "sha256:")
		if err := os.Chtimes(filepath.Join(s.root, "sha256", hex[:2], hex), at, at); err != nil {
			s.t.Fatal(err)
		}
	}
}

// Temp lists what is left in the store's folder of temporary files.
func (s *Store) Temp() []os.DirEntry {
	s.t.Helper()
	ents, err := os.ReadDir(filepath.Join(s.root, "tmp"))
	if err != nil {
		s.t.Fatal(err)
	}
	return ents
}
