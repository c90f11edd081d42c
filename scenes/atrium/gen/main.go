// Command gen writes the atrium demonstration scene (package atrium) into a folder.
package main

import (
	"flag"
	"fmt"
	"os"

	"photonfarm/scenes/atrium"
)

func main() {
	out := flag.String("o", ".", "output `folder`")
	flag.Parse()
	st, err := atrium.Write(*out)
	if err != nil {
		fmt.Fprintln(os.Stderr, "atrium:", err)
		os.Exit(1)
	}
	fmt.Printf("atrium: %d triangles, %d textures, %d nodes, written to %s\n", st.Triangles, st.Textures, st.Nodes, *out)
}
