package main

import (
	"testing"

	"photonfarm/tests/vectors/vectorfiles"
)

const root = "../../../.."

// TestCommittedVectorsAreCurrent fails while the committed farm grid vectors differ from
// what the generator makes.
func TestCommittedVectorsAreCurrent(t *testing.T) {
	vectorfiles.Check(t, root, Vectors(), "go run ./tests/vectors/grids/gen", owned)
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
