// Command gen writes the farm grid vectors of tests/vectors/grids (README.md there): each
// NAME.farmgrid beside NAME.farmgrid.vector, whose one line says what every reader must
// make of it. Run from the repository's root after changing a case:
//
//	go run ./tests/vectors/grids/gen
//
// and commit the result; gen_test.go fails while the committed files differ from what it
// makes.
package main

import (
	"fmt"
	"path"

	"photonfarm/tests/vectors/vectorfiles"
)

// vectorDir is the folder of the grid vectors, from the repository's root; owned, the
// files of it the generator makes.
const (
	vectorDir = "tests/vectors/grids"
	owned     = vectorDir + "/*.farmgrid*"
)

func main() {
	vectorfiles.Main("gen", func(string) (map[string][]byte, error) { return Vectors(), nil }, owned)
}

// Vectors returns the files the generator makes, by path from the repository's root.
func Vectors() map[string][]byte {
	files := map[string][]byte{}
	for _, c := range cases() {
		file := path.Join(vectorDir, c.name+".farmgrid")
		files[file] = c.file
		files[file+".vector"] = []byte(verdict(c) + "\n")
	}
	return files
}

// verdict is the line of a case's sidecar: "# vector: accept" or "# vector: refuse byte N:
// REASON", as a farm mesh vector's.
func verdict(c gridCase) string {
	if c.reason == "" {
		return "# vector: accept"
	}
	return fmt.Sprintf("# vector: refuse byte %d: %s", c.offset, c.reason)
}
