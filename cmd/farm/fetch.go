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
	name := fs.String("name", "", "base `name` of the files (default: the job's display name)")
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
