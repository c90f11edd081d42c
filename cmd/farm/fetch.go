package main

import (
	"context"
	"fmt"

	"photonfarm/client"
)

var fetchVerb = &verb{
	name:    "fetch",
	args:    "JOB -o DIR [--name NAME] [--coordinator ADDR]",
	summary: "download a succeeded job's EXR and PNG preview",
	run:     runFetch,
}

func runFetch(ctx context.Context, e *env, args []string) error {
	fs := newFlags("fetch", e)
	out := fs.String("o", ".", "output `folder` (created if missing)")
	name := outputNameFlag(fs)
	return withClient(fs, e, args, 1, 1, func(c *client.Client, pos []string) error {
		paths, err := c.FetchAs(ctx, pos[0], *out, *name)
		if err != nil {
			return err
		}
		for _, p := range paths {
			fmt.Fprintln(e.stdout, p)
		}
		return nil
	})
}

// outputNameFlag adds --name to fs: farm render and farm fetch name the outputs alike.
func outputNameFlag(fs *flagSet) *string {
	return fs.String("name", "", "base `name` of the EXR and PNG (default: the job's display name, the scene's name field, made file-safe; a scene without one is named after its file)")
}
