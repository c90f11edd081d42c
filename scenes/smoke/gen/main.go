// Command gen writes the smoke demonstration scene (package smoke) into a folder:
// smoke.json and the plume's grid file, plume.farmgrid.
package main

import (
	"flag"
	"fmt"
	"os"

	"photonfarm/scenes/smoke"
)

func main() {
	out := flag.String("o", ".", "output `folder`")
	flag.Parse()
	if err := smoke.Write(*out); err != nil {
		fmt.Fprintln(os.Stderr, "smoke:", err)
		os.Exit(1)
	}
	fmt.Printf("smoke: smoke.json and plume.farmgrid written to %s\n", *out)
}
