package main

import (
	"context"
	"fmt"

	"photonfarm/client"
)

var submitVerb = &verb{
	name:    "submit",
	args:    "SCENE [--coordinator ADDR] [--priority N] [--watch] [--asset-root DIR]",
	summary: "submit a scene file; prints the job id",
	run:     runSubmit,
}

func runSubmit(ctx context.Context, e *env, args []string) error {
	fs := newFlags("submit", e)
	watch := fs.Bool("watch", false, "after submitting, show progress until the job ends (like farm watch)")
	assetRoot := assetRootFlag(fs)
	priority := fs.Int("priority", 0, "the job's priority in [-1000, 1000]: higher runs first")
	return withClient(fs, e, args, 1, 1, func(c *client.Client, pos []string) error {
		prio, err := submitPriority(*priority)
		if err != nil {
			return err
		}
		sc, err := c.LoadSceneFile(ctx, pos[0], client.WithAssetRoot(*assetRoot))
		if err != nil {
			return err
		}
		job, err := c.Submit(ctx, sc, prio, client.WithRequestID(client.NewRequestID()))
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
