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
	var names []string
	var files [][]byte
	for _, c := range cases() {
		names, files = append(names, c.name), append(files, c.file)
	}
	vectorfiles.CheckDistinct(t, names, files)
}
