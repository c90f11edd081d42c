package main

import (
	"context"
	"fmt"
	"runtime"
	"runtime/debug"
)

// farmVersion is the release, the same as farm-worker's (worker/daemon/version.h).
const farmVersion = "0.1.0"

var versionVerb = &verb{
	name:    "version",
	summary: "print farm's version, the commit it was built from and the Go version (also farm --version)",
	run:     runVersion,
}

func runVersion(_ context.Context, e *env, args []string) error {
	if _, err := parse(newFlags("version", e), args, 0, 0); err != nil {
		return err
	}
	info, _ := debug.ReadBuildInfo()
	fmt.Fprintln(e.stdout, versionLine(info))
	return nil
}

// versionLine is "farm 0.1.0 (commit f537d7e, modified; go1.24.1)": the commit is go
// build's record of the checkout it built (absent from test binaries and go run).
func versionLine(info *debug.BuildInfo) string {
	commit, modified := "", false
	if info != nil {
		for _, s := range info.Settings {
			switch s.Key {
			case "vcs.revision":
				commit = s.Value
			case "vcs.modified":
				modified = s.Value == "true"
			}
		}
	}
	build := runtime.Version()
	if commit != "" {
		build = "commit " + commit[:min(len(commit), 7)]
		if modified {
			build += ", modified"
		}
		build += "; " + runtime.Version()
	}
	return fmt.Sprintf("farm %s (%s)", farmVersion, build)
}
