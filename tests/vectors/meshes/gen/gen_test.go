package main

import (
	"bytes"
	"os"
	"path/filepath"
	"testing"
)

const root = "../../../.."

// TestCommittedVectorsAreCurrent fails while the committed farm mesh vectors differ from
// what the generator makes: run `go run ./tests/vectors/meshes/gen`.
func TestCommittedVectorsAreCurrent(t *testing.T) {
	files := Vectors()
	for rel, want := range files {
		got, err := os.ReadFile(filepath.Join(root, rel))
		if err != nil || !bytes.Equal(got, want) {
			t.Errorf("%s is not what the generator makes (%v): run go run ./tests/vectors/meshes/gen", rel, err)
		}
	}
	committed, err := filepath.Glob(filepath.Join(root, vectorDir, "*.farmmesh*"))
	if err != nil {
		t.Fatal(err)
	}
	for _, p := range committed {
		if rel, _ := filepath.Rel(root, p); files[rel] == nil {
			t.Errorf("%s is not made by the generator: run go run ./tests/vectors/meshes/gen", rel)
		}
	}
}

// TestCasesAreDistinct: no two cases share a name or, by accident, a file.
func TestCasesAreDistinct(t *testing.T) {
	names, files := map[string]bool{}, map[string]string{}
	for _, c := range cases() {
		if names[c.name] {
			t.Errorf("two cases are called %s", c.name)
		}
		names[c.name] = true
		if other, dup := files[string(c.file)]; dup {
			t.Errorf("%s and %s are the same file", c.name, other)
		}
		files[string(c.file)] = c.name
	}
}
