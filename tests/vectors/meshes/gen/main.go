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
	"flag"
	"fmt"
	"os"
	"path/filepath"
	"strings"
)

// vectorDir is the folder of the mesh vectors, from the repository's root.
const vectorDir = "tests/vectors/meshes"

func main() {
	root := flag.String("root", ".", "the repository's root")
	flag.Parse()
	if err := write(*root); err != nil {
		fmt.Fprintln(os.Stderr, "gen:", err)
		os.Exit(1)
	}
}

// Vectors returns the files the generator makes, by path from the repository's root.
func Vectors() map[string][]byte {
	files := map[string][]byte{}
	for _, c := range cases() {
		file := filepath.Join(vectorDir, c.name+".farmmesh")
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

// write writes every file Vectors makes and removes the farm mesh vectors it no longer makes.
func write(root string) error {
	files := Vectors()
	stale, err := filepath.Glob(filepath.Join(root, vectorDir, "*.farmmesh*"))
	if err != nil {
		return err
	}
	for _, p := range stale {
		if rel, _ := filepath.Rel(root, p); files[rel] == nil && strings.Contains(p, ".farmmesh") {
			if err := os.Remove(p); err != nil {
				return err
			}
		}
	}
	for rel, data := range files {
		if err := os.WriteFile(filepath.Join(root, rel), data, 0o644); err != nil {
			return err
		}
	}
	fmt.Printf("gen: %d files under %s\n", len(files), vectorDir)
	return nil
}
