// Package vectorfiles writes and checks the files a vector generator makes
// (tests/vectors/scenes/gen, tests/vectors/meshes/gen, tests/vectors/grids/gen): the files, by path from the
// repository's root, and the glob patterns of the files the generator owns, so that one it
// no longer makes is removed, or reported.
package vectorfiles

import (
	"bytes"
	"encoding/binary"
	"flag"
	"fmt"
	"math"
	"os"
	"path/filepath"
	"testing"
)

// Main is a generator's main: it writes the files generate returns under -root (the
// repository's root, "." by default) and exits 1 on an error.
func Main(name string, generate func(root string) (map[string][]byte, error), owned ...string) {
	root := flag.String("root", ".", "the repository's root")
	flag.Parse()
	files, err := generate(*root)
	if err == nil {
		err = Write(*root, files, owned...)
	}
	if err != nil {
		fmt.Fprintln(os.Stderr, name+":", err)
		os.Exit(1)
	}
	fmt.Printf("%s: %d files written\n", name, len(files))
}

// Write writes files under root, and removes the files under root that match a pattern
// of owned and are not among them.
func Write(root string, files map[string][]byte, owned ...string) error {
	stale, err := strays(root, files, owned)
	if err != nil {
		return err
	}
	for _, p := range stale {
		if err := os.Remove(filepath.Join(root, p)); err != nil {
			return err
		}
	}
	for rel, data := range files {
		p := filepath.Join(root, rel)
		if err := os.MkdirAll(filepath.Dir(p), 0o755); err != nil {
			return err
		}
		if err := os.WriteFile(p, data, 0o644); err != nil {
			return err
		}
	}
	return nil
}

// Check fails t for each of files whose committed copy under root differs, and for each
// committed file matching a pattern of owned that files does not have; run says how to
// make them current.
func Check(t testing.TB, root string, files map[string][]byte, run string, owned ...string) {
	t.Helper()
	for rel, want := range files {
		got, err := os.ReadFile(filepath.Join(root, rel))
		if err != nil || !bytes.Equal(got, want) {
			t.Errorf("%s is not what the generator makes (%v): run %s", rel, err, run)
		}
	}
	stale, err := strays(root, files, owned)
	if err != nil {
		t.Fatal(err)
	}
	for _, rel := range stale {
		t.Errorf("%s is not made by the generator: run %s", rel, run)
	}
}

// strays lists the files under root matching a pattern of owned that files does not have.
func strays(root string, files map[string][]byte, owned []string) ([]string, error) {
	var out []string
	for _, pattern := range owned {
		found, err := filepath.Glob(filepath.Join(root, pattern))
		if err != nil {
			return nil, err
		}
		for _, p := range found {
			rel, err := filepath.Rel(root, p)
			if err != nil {
				return nil, err
			}
			if files[filepath.ToSlash(rel)] == nil {
				out = append(out, filepath.ToSlash(rel))
			}
		}
	}
	return out, nil
}

// CheckDistinct fails t for two cases of the same name, or, by accident, the same file.
func CheckDistinct(t testing.TB, names []string, files [][]byte) {
	t.Helper()
	seen, byFile := map[string]bool{}, map[string]string{}
	for i, name := range names {
		if seen[name] {
			t.Errorf("two cases are called %s", name)
		}
		seen[name] = true
		if other, dup := byFile[string(files[i])]; dup {
			t.Errorf("%s and %s are the same file", name, other)
		}
		byFile[string(files[i])] = name
	}
}

// Put32 is a copy of b with the little-endian uint32 at `at` set to v.
func Put32(b []byte, at int, v uint32) []byte {
	b = bytes.Clone(b)
	binary.LittleEndian.PutUint32(b[at:], v)
	return b
}

// Float32 is a copy of b with the little-endian float32 at `at` set to x.
func Float32(b []byte, at int, x float32) []byte { return Put32(b, at, math.Float32bits(x)) }
