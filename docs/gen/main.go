// Command gen regenerates the parts of docs/limits.md that the contract declares (the
// scene rules and limits, the RPC limits, and the figures that follow from them), between
// its "generated" marker comments, from the options of proto/renderfarm/v1 read through
// contract/rules. Run from the repository's root after changing an option:
//
//	go run ./docs/gen
//
// main_test.go fails while docs/limits.md is not what it makes.
package main

import (
	"fmt"
	"os"
	"path/filepath"
)

// page is the file gen rewrites, from the repository's root.
const page = "docs/limits.md"

func main() {
	root := "."
	if len(os.Args) > 1 {
		root = os.Args[1]
	}
	path := filepath.Join(root, page)
	old, err := os.ReadFile(path)
	if err == nil {
		var updated string
		if updated, err = Update(string(old)); err == nil {
			err = os.WriteFile(path, []byte(updated), 0o644)
		}
	}
	if err != nil {
		fmt.Fprintln(os.Stderr, "gen:", err)
		os.Exit(1)
	}
}
