package main

import (
	"context"
	"fmt"
	"io"
	"strings"
	"text/tabwriter"
	"time"

	"photonfarm/client"
	"photonfarm/contract/tasks"
	pb "photonfarm/proto/renderfarm/v1"
)

var statusVerb = &verb{
	name:    "status",
	args:    "JOB [--coordinator ADDR]",
	summary: "show a job: state, phases, outputs, error",
	run:     runStatus,
}

var listVerb = &verb{
	name:    "list",
	args:    "[--coordinator ADDR]",
	summary: "list jobs, newest first",
	run:     runList,
}

var tasksVerb = &verb{
	name:    "tasks",
	args:    "JOB [--coordinator ADDR]",
	summary: "list a job's tasks: state, attempts, worker",
	run:     runTasks,
}

var cancelVerb = &verb{
	name:    "cancel",
	args:    "JOB [--coordinator ADDR]",
	summary: "cancel a job that has not ended",
	run:     runCancel,
}

var requeueVerb = &verb{
	name:    "requeue",
	args:    "JOB [--coordinator ADDR]",
	summary: "reopen a failed or cancelled job where it stopped",
	run:     runRequeue,
}

var retryVerb = &verb{
	name:    "retry",
	args:    "TASK [--coordinator ADDR]",
	summary: "queue a failed task again (as 'farm tasks' names it), reopening its job",
	run:     runRetry,
}

var deleteVerb = &verb{
	name:    "delete",
	args:    "JOB [--coordinator ADDR]",
	summary: "delete a job and its tasks (cancelling it first if it runs); its blobs go after the blob grace",
	run:     runDelete,
}

func runStatus(ctx context.Context, e *env, args []string) error {
	return withClient(newFlags("status", e), e, args, 1, 1, func(c *client.Client, pos []string) error {
		job, err := c.GetJob(ctx, pos[0])
		if err != nil {
			return err
		}
		printJob(e.stdout, job, time.Now())
		return nil
	})
}

func printJob(w io.Writer, job *pb.Job, now time.Time) {
	tw := tabwriter.NewWriter(w, 0, 4, 2, ' ', 0)
	fmt.Fprintf(tw, "job\t%s\n", printable(job.GetId()))
	fmt.Fprintf(tw, "name\t%s\n", printable(job.GetDisplayName()))
	fmt.Fprintf(tw, "state\t%s\n", tasks.JobStateName(job.GetState()))
	fmt.Fprintf(tw, "priority\t%d\n", job.GetPriority())
	fmt.Fprintf(tw, "image\t%dx%d\n", job.GetWidth(), job.GetHeight())
	if t := job.GetCreateTime(); t != nil {
		fmt.Fprintf(tw, "created\t%s\n", t.AsTime().Local().Format(time.DateTime))
	}
	if t := job.GetEndTime(); t != nil && job.GetCreateTime() != nil {
		fmt.Fprintf(tw, "took\t%s\n", t.AsTime().Sub(job.GetCreateTime().AsTime()).Round(time.Millisecond))
	} else if t := job.GetCreateTime(); t != nil {
		fmt.Fprintf(tw, "age\t%s\n", now.Sub(t.AsTime()).Round(time.Second))
	}
	for _, ph := range job.GetPhases() {
		fmt.Fprintf(tw, "phase %s\t%d/%d tasks\n", tasks.Name(ph.GetPhase()), ph.GetTasksSucceeded(), ph.GetTasksTotal())
	}
	for _, a := range job.GetOutputs() {
		fmt.Fprintf(tw, "output %s\t%s (%d bytes)\n", printable(a.GetName()), printable(a.GetDigest()), a.GetSizeBytes())
	}
	for _, b := range job.GetBlockedWorkers() {
		fmt.Fprintf(tw, "blocked %s\t%s (since %s)\n", printable(b.GetWorkerId()), oneLine(b.GetReason()),
			b.GetBlockTime().AsTime().Local().Format(time.DateTime))
	}
	if job.GetError() != "" {
		fmt.Fprintf(tw, "error\t%s\n", oneLine(jobFailure(job)))
	}
	tw.Flush()
}

func runList(ctx context.Context, e *env, args []string) error {
	return withClient(newFlags("list", e), e, args, 0, 0, func(c *client.Client, _ []string) error {
		jobs, err := c.ListJobs(ctx)
		if err != nil {
			return err
		}
		tw := tabwriter.NewWriter(e.stdout, 0, 4, 2, ' ', 0)
		fmt.Fprintln(tw, "JOB\tNAME\tSTATE\tPRIORITY\tPROGRESS\tSIZE\tCREATED")
		for _, j := range jobs {
			created := ""
			if t := j.GetCreateTime(); t != nil {
				created = t.AsTime().Local().Format(time.DateTime)
			}
			fmt.Fprintf(tw, "%s\t%s\t%s\t%d\t%s\t%dx%d\t%s\n", printable(j.GetId()), printable(j.GetDisplayName()),
				tasks.JobStateName(j.GetState()), j.GetPriority(), phaseSummary(j), j.GetWidth(), j.GetHeight(), created)
		}
		return tw.Flush()
	})
}

// phaseSummary is "render 12/48, composite 0/1".
func phaseSummary(j *pb.Job) string {
	var parts []string
	for _, ph := range j.GetPhases() {
		parts = append(parts, fmt.Sprintf("%s %d/%d", tasks.Name(ph.GetPhase()), ph.GetTasksSucceeded(), ph.GetTasksTotal()))
	}
	return strings.Join(parts, ", ")
}

func runTasks(ctx context.Context, e *env, args []string) error {
	return withClient(newFlags("tasks", e), e, args, 1, 1, func(c *client.Client, pos []string) error {
		list, err := c.ListTasks(ctx, pos[0])
		if err != nil {
			return err
		}
		tw := tabwriter.NewWriter(e.stdout, 0, 4, 2, ' ', 0)
		fmt.Fprintln(tw, "TASK\tPHASE\tSTATE\tATTEMPTS\tWORKER\tWORK\tERROR")
		for _, t := range list {
			fmt.Fprintf(tw, "%s\t%s\t%s\t%d\t%s\t%s\t%s\n", printable(t.GetId()), tasks.Name(t.GetPhase()),
				tasks.TaskStateName(t.GetState()), t.GetAttempts(), printable(t.GetWorkerId()), taskWork(t), oneLine(t.GetError()))
		}
		return tw.Flush()
	})
}

// taskWork says what a task covers: a tile's rectangle ("16x16+32+0") or an emission
// shard's photon paths ("caustic 10000+10000/40000").
func taskWork(t *pb.Task) string {
	if r := t.GetRenderTile().GetRect(); r != nil {
		return fmt.Sprintf("%dx%d+%d+%d", r.GetWidth(), r.GetHeight(), r.GetX(), r.GetY())
	}
	if e := t.GetEmitPhotons(); e != nil {
		return fmt.Sprintf("%s %d+%d/%d", tasks.MapName(e.GetMap()), e.GetFirstPhoton(), e.GetPhotonCount(), e.GetTotalPhotons())
	}
	return ""
}

func runCancel(ctx context.Context, e *env, args []string) error {
	return withClient(newFlags("cancel", e), e, args, 1, 1, func(c *client.Client, pos []string) error {
		job, err := c.Cancel(ctx, pos[0])
		if err != nil {
			return err
		}
		fmt.Fprintf(e.stdout, "job %s %s\n", printable(job.GetId()), tasks.JobStateName(job.GetState()))
		return nil
	})
}

func runRequeue(ctx context.Context, e *env, args []string) error {
	return withClient(newFlags("requeue", e), e, args, 1, 1, func(c *client.Client, pos []string) error {
		job, err := c.Requeue(ctx, pos[0])
		if err != nil {
			return err
		}
		fmt.Fprintf(e.stdout, "job %s %s\n", printable(job.GetId()), tasks.JobStateName(job.GetState()))
		return nil
	})
}

func runRetry(ctx context.Context, e *env, args []string) error {
	return withClient(newFlags("retry", e), e, args, 1, 1, func(c *client.Client, pos []string) error {
		job, task, err := c.RetryTask(ctx, pos[0])
		if err != nil {
			return err
		}
		fmt.Fprintf(e.stdout, "task %s %s; job %s %s\n", printable(task.GetId()), tasks.TaskStateName(task.GetState()),
			printable(job.GetId()), tasks.JobStateName(job.GetState()))
		return nil
	})
}

func runDelete(ctx context.Context, e *env, args []string) error {
	return withClient(newFlags("delete", e), e, args, 1, 1, func(c *client.Client, pos []string) error {
		job, err := c.Delete(ctx, pos[0])
		if err != nil {
			return err
		}
		fmt.Fprintf(e.stdout, "job %s deleted (was %s)\n", printable(job.GetId()), tasks.JobStateName(job.GetState()))
		return nil
	})
}
