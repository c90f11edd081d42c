package main

import (
	"context"
	"fmt"
	"regexp"
	"strconv"

	"photonfarm/client"
)

var priorityVerb = &verb{
	name:    "priority",
	args:    "JOB N [--coordinator ADDR]",
	summary: "set a job's priority, in [-1000, 1000] (higher runs first)",
	run:     runPriority,
}

var unblockVerb = &verb{
	name:    "unblock",
	args:    "JOB [WORKER] [--coordinator ADDR]",
	summary: "let a blocked worker (or every one) lease a job's tasks again",
	run:     runUnblock,
}

// negativeNumber matches an argument the flag package would take for a flag.
var negativeNumber = regexp.MustCompile(`^-[0-9]+$`)

func runPriority(ctx context.Context, e *env, args []string) error {
	fs := newFlags("priority", e)
	// "farm priority JOB -5": a negative N is an argument, not a flag.
	var flagArgs, numbers []string
	for _, a := range args {
		if negativeNumber.MatchString(a) {
			numbers = append(numbers, a)
		} else {
			flagArgs = append(flagArgs, a)
		}
	}
	return withClient(fs, e, flagArgs, 1, 2, func(c *client.Client, pos []string) error {
		if pos = append(pos, numbers...); len(pos) != 2 {
			return usageErrorf("priority: wrong number of arguments (see 'farm priority -h')")
		}
		p, err := strconv.ParseInt(pos[1], 10, 32)
		if err != nil {
			return usageErrorf("priority: N must be an integer in [-1000, 1000], got %q", pos[1])
		}
		job, err := c.SetJobPriority(ctx, pos[0], int32(p))
		if err != nil {
			return err
		}
		fmt.Fprintf(e.stdout, "job %s priority %d\n", printable(job.GetId()), job.GetPriority())
		return nil
	})
}

func runUnblock(ctx context.Context, e *env, args []string) error {
	return withClient(newFlags("unblock", e), e, args, 1, 2, func(c *client.Client, pos []string) error {
		worker := ""
		if len(pos) == 2 {
			worker = pos[1]
		}
		job, err := c.UnblockWorker(ctx, pos[0], worker)
		if err != nil {
			return err
		}
		fmt.Fprintf(e.stdout, "job %s: %d blocked workers\n", printable(job.GetId()), len(job.GetBlockedWorkers()))
		return nil
	})
}

// submitPriority is submit's --priority as a client option.
func submitPriority(p int) (client.SubmitOption, error) {
	if p < -1000 || p > 1000 {
		return nil, usageErrorf("submit: --priority must be in [-1000, 1000], got %d", p)
	}
	return client.WithPriority(int32(p)), nil
}
