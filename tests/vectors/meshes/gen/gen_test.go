package main

import (
	"testing"

	"photonfarm/tests/vectors/vectorfiles"
)

const root = "../../../.."

// TestCommittedVectorsAreCurrent fails while the committed farm mesh vectors differ from
// what the generator makes.
func TestCommittedVectorsAreCurrent(t *testing.T) {
	vectorfiles.Check(t, root, Vectors(), "go run ./tests/vectors/meshes/gen", owned)
}

// TestCasesAreDistinct: no two cases share a name or, by accident, a file.
func TestCasesAreDistinct(t *testing.T) {
	vectorfiles.CheckDistinctCases(t, cases())
}
