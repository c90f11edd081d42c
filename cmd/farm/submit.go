package main

import (
	"context"
	"fmt"

	"photonfarm/client"
)

var submitVerb = &verb{
	name:    "submit",
	args:    "SCENE|MODEL [--coordinator ADDR] [--priority N] [--watch] [--asset-root DIR] [--width N] [--height N]",
	summary: "submit a scene file; prints the job id",
	run:     runSubmit,
}

func runSubmit(ctx context.Context, e *env, args []string) error {
	fs := newFlags("submit", e)
	watch := fs.Bool("watch", false, "after submitting, show progress until the job ends (like farm watch)")
	assetRoot := assetRootFlag(fs)
	priority := fs.Int("priority", 0, "the job's priority in [-1000, 1000]: higher runs first")
	imports := importFlags(fs)
	return withClient(fs, e, args, 1, 1, func(c *client.Client, pos []string) error {
		prio, err := submitPriority(*priority)
		if err != nil {
			return err
		}
		// The job id goes alone on stdout, for scripts: what an import did goes to stderr.
		sf, cleanup, err := checkScene(ctx, e.stderr, pos[0], *assetRoot, imports())
		if err != nil {
			return err
		}
		defer cleanup()
		if err := c.Upload(ctx, sf); err != nil {
			return err
		}
		job, err := c.Submit(ctx, sf.Scene, prio, client.WithRequestID(client.NewRequestID()))
		if err != nil {
			return err
		}
		fmt.Fprintln(e.stdout, printable(job.GetId()))
		if *watch {
			return watchJob(ctx, e, c, job.GetId())
		}
		return nil
	})
}
