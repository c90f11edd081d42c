// Command gen writes the farm mesh vectors of tests/vectors/meshes (README.md there): each
// NAME.farmmesh beside NAME.farmmesh.vector, whose one line says what every reader must
// make of it. Run from the repository's root after changing a case:
//
//	go run ./tests/vectors/meshes/gen
//
// and commit the result; gen_test.go fails while the committed files differ from what it
// makes.
package main

import "photonfarm/tests/vectors/vectorfiles"

// vectorDir is the folder of the mesh vectors, from the repository's root; owned, the
// files of it the generator makes (the OBJ vectors are written by hand).
const (
	vectorDir = "tests/vectors/meshes"
	owned     = vectorDir + "/*.farmmesh*"
)

func main() {
	vectorfiles.Main("gen", func(string) (map[string][]byte, error) { return Vectors(), nil }, owned)
}

// Vectors returns the files the generator makes, by path from the repository's root.
func Vectors() map[string][]byte {
	return vectorfiles.BinaryVectors(vectorDir, ".farmmesh", cases())
}
