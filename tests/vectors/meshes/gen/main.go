// Command gen writes the farm mesh vectors of tests/vectors/meshes (README.md there): each
// NAME.farmmesh beside NAME.farmmesh.vector, whose one line says what every reader must
// make of it. Run from the repository's root after changing a case:
//
//	go run ./tests/vectors/meshes/gen
//
// and commit the result; gen_test.go fails while the committed files differ from what it
// makes.
package main

import (
	"fmt"
	"path"

	"photonfarm/tests/vectors/vectorfiles"
)

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
	files := map[string][]byte{}
	for _, c := range cases() {
		file := path.Join(vectorDir, c.name+".farmmesh")
		files[file] = c.file
		files[file+".vector"] = []byte(verdict(c) + "\n")
	}
	return files
}

// verdict is the line of a case's sidecar: "# vector: accept" or "# vector: refuse byte N:
// REASON", as an OBJ vector's first line says "refuse line N".
func verdict(c farmCase) string {
	if c.reason == "" {
		return "# vector: accept"
	}
	return fmt.Sprintf("# vector: refuse byte %d: %s", c.offset, c.reason)
}
