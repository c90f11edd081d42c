package main

import (
	"bytes"
	"context"
	"fmt"
	"time"

	"google.golang.org/protobuf/proto"

	"photonfarm/client"
	"photonfarm/contract/scene"
	"photonfarm/contract/tasks"
	pb "photonfarm/proto/renderfarm/v1"
)

var watchVerb = &verb{
	name:    "watch",
	args:    "JOB [--coordinator ADDR]",
	summary: "show a job's progress until it ends; exit 0 only if it succeeded",
	run:     runWatch,
}

func runWatch(ctx context.Context, e *env, args []string) error {
	return withClient(newFlags("watch", e), e, args, 1, 1, func(c *client.Client, pos []string) error {
		return watchJob(ctx, e, c, pos[0])
	})
}

// watchJob shows the job's progress on stdout until it ends and returns nil only if it
// succeeded.
func watchJob(ctx context.Context, e *env, c *client.Client, jobID string) error {
	p := newProgress(e.stdout, isTerminal(e.stdout), time.Now, plannedRounds(ctx, c, jobID))
	stop := p.start()
	job, err := c.Watch(ctx, jobID, func(ev *pb.WatchJobResponse) { p.update(ev.GetJob(), ev.GetTime().AsTime()) })
	stop(job)
	if err != nil {
		return err
	}
	return jobOutcome(job)
}

// plannedRounds is the number of progressive rounds the job's scene asks for (the job
// may stop earlier), read from the scene as stored (defaults filled in); 0 if it cannot
// be read, and the progress then counts the rounds it sees.
func plannedRounds(ctx context.Context, c *client.Client, jobID string) int {
	job, err := c.GetJob(ctx, jobID)
	if err != nil {
		return 0
	}
	var buf bytes.Buffer
	if _, err := c.Download(ctx, job.GetSceneDigest(), &buf); err != nil {
		return 0
	}
	sc := &pb.Scene{}
	if err := proto.Unmarshal(buf.Bytes(), sc); err != nil {
		return 0
	}
	return int(scene.Rounds(sc))
}

// jobFailure is a failed job's reason for people, its failure kind's label first when the
// coordinator says it: "bad input: task j-1.3 failed: shapes[8].mesh: ...".
func jobFailure(job *pb.Job) string {
	if k := job.GetFailureKind(); k != pb.FailureKind_FAILURE_KIND_UNSPECIFIED {
		return tasks.FailureOf(k).Label + ": " + job.GetError()
	}
	return job.GetError()
}

// jobOutcome is nil for a succeeded job and an error saying how it ended otherwise.
func jobOutcome(job *pb.Job) error {
	switch job.GetState() {
	case pb.JobState_JOB_STATE_SUCCEEDED:
		return nil
	case pb.JobState_JOB_STATE_FAILED:
		return &exitError{code: exitFailure, err: fmt.Errorf("job %s failed: %s", job.GetId(), jobFailure(job))}
	}
	return &exitError{code: exitFailure, err: fmt.Errorf("job %s ended %s", job.GetId(), tasks.JobStateName(job.GetState()))}
}
