// Command gen writes the shared scene conformance vectors, tests/vectors/scenes/*.json
// (README.md there), from a valid base scene and one change each, and the mesh file they
// name. Run from the repository's root after changing a rule or a case:
//
//	go run ./tests/vectors/scenes/gen
//
// and commit the result; gen_test.go fails while the committed files differ from what it
// makes, or while a rule of scene.proto has no vector.
package main

import (
	"flag"
	"fmt"
	"os"
	"path/filepath"
)

func main() {
	root := flag.String("root", ".", "the repository's root")
	flag.Parse()
	if err := write(*root); err != nil {
		fmt.Fprintln(os.Stderr, "gen:", err)
		os.Exit(1)
	}
}

// write writes every file Vectors makes and removes the vectors it no longer makes.
func write(root string) error {
	files, err := Vectors(root)
	if err != nil {
		return err
	}
	stale, err := filepath.Glob(filepath.Join(root, vectorDir, "*.json"))
	if err != nil {
		return err
	}
	for _, p := range stale {
		if rel, _ := filepath.Rel(root, p); files[filepath.ToSlash(rel)] == nil {
			if err := os.Remove(p); err != nil {
				return err
			}
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
	fmt.Printf("gen: %d files under tests/vectors\n", len(files))
	return nil
}
