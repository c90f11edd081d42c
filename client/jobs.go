package client

import (
	"context"
	"crypto/rand"
	"errors"
	"fmt"
	"io"
	"os"
	"path/filepath"
	"strings"
	"time"

	"google.golang.org/grpc/codes"
	"google.golang.org/protobuf/proto"

	"photonfarm/contract/pages"
	"photonfarm/contract/tasks"
	pb "photonfarm/proto/renderfarm/v1"
)

// A SubmitOption configures Submit.
type SubmitOption func(*pb.SubmitJobRequest)

// WithPriority submits the job with priority p, in [-1000, 1000] (default 0): higher
// jobs are leased first.
func WithPriority(p int32) SubmitOption {
	return func(r *pb.SubmitJobRequest) { r.Priority = p }
}

// WithRequestID names the submission (at most 128 printable ASCII characters, NewRequestID
// makes one): a repeated Submit with the same id returns the job the first one created, so
// a caller may retry a submit whose answer it lost.
func WithRequestID(id string) SubmitOption {
	return func(r *pb.SubmitJobRequest) { r.RequestId = id }
}

// NewRequestID returns a fresh random request id (128 random bits).
func NewRequestID() string { return rand.Text() }

// Submit queues scene as a new job. The scene's meshes must be in the blob store already
// (LoadSceneFile does that). A malformed scene (or priority) gives an *Error with code
// InvalidArgument naming the field.
func (c *Client) Submit(ctx context.Context, sc *pb.Scene, opts ...SubmitOption) (*pb.Job, error) {
	req := &pb.SubmitJobRequest{Scene: sc}
	for _, o := range opts {
		o(req)
	}
	resp, err := c.jobs.SubmitJob(ctx, req)
	if err != nil {
		return nil, fromRPC("submit job", err)
	}
	return resp.GetJob(), nil
}

// SetJobPriority changes the priority of a job that has not ended (leases granted
// already stand).
func (c *Client) SetJobPriority(ctx context.Context, jobID string, priority int32) (*pb.Job, error) {
	resp, err := c.jobs.SetJobPriority(ctx, &pb.SetJobPriorityRequest{JobId: jobID, Priority: priority})
	if err != nil {
		return nil, fromRPC("set job priority", err)
	}
	return resp.GetJob(), nil
}

// UnblockWorker lets workerID (every blocked worker if empty) lease the job's tasks again.
func (c *Client) UnblockWorker(ctx context.Context, jobID, workerID string) (*pb.Job, error) {
	resp, err := c.jobs.UnblockWorker(ctx, &pb.UnblockWorkerRequest{JobId: jobID, WorkerId: workerID})
	if err != nil {
		return nil, fromRPC("unblock worker", err)
	}
	return resp.GetJob(), nil
}

// PlanScene returns what the coordinator would run for sc, without creating a job: the
// passes it runs and skips, and the tasks per phase of the first round. A malformed scene
// gives an *Error with code InvalidArgument naming the field.
func (c *Client) PlanScene(ctx context.Context, sc *pb.Scene) (*pb.PlanSceneResponse, error) {
	resp, err := c.jobs.PlanScene(ctx, &pb.PlanSceneRequest{Scene: sc})
	if err != nil {
		return nil, fromRPC("plan scene", err)
	}
	return resp, nil
}

// GetJob returns the job jobID.
func (c *Client) GetJob(ctx context.Context, jobID string) (*pb.Job, error) {
	resp, err := c.jobs.GetJob(ctx, &pb.GetJobRequest{JobId: jobID})
	if err != nil {
		return nil, fromRPC("get job", err)
	}
	return resp.GetJob(), nil
}

// Page sizes the SDK asks for: the coordinator's largest (job.proto).
const (
	jobsPage    = 1000
	tasksPage   = 10000
	workersPage = 1000
)

// ListJobs returns every job, newest first, following the pages.
func (c *Client) ListJobs(ctx context.Context) ([]*pb.Job, error) {
	return AllJobs(ctx, c.jobs)
}

// ListTasks returns every task of the job, in plan order, following the pages.
func (c *Client) ListTasks(ctx context.Context, jobID string) ([]*pb.Task, error) {
	return AllTasks(ctx, c.jobs, jobID)
}

// AllJobs lists every job through jobs (a JobService client of the caller's, such as the
// dashboard's, whose calls carry per-request credentials), newest first.
func AllJobs(ctx context.Context, jobs pb.JobServiceClient) ([]*pb.Job, error) {
	return pages.All(func(token string) ([]*pb.Job, string, error) {
		resp, err := jobs.ListJobs(ctx, &pb.ListJobsRequest{PageSize: jobsPage, PageToken: token})
		return resp.GetJobs(), resp.GetNextPageToken(), fromRPC("list jobs", err)
	})
}

// AllTasks lists every task of a job through jobs, in plan order.
func AllTasks(ctx context.Context, jobs pb.JobServiceClient, jobID string) ([]*pb.Task, error) {
	return pages.All(func(token string) ([]*pb.Task, string, error) {
		resp, err := jobs.ListTasks(ctx, &pb.ListTasksRequest{JobId: jobID, PageSize: tasksPage, PageToken: token})
		return resp.GetTasks(), resp.GetNextPageToken(), fromRPC("list tasks", err)
	})
}

// ListWorkers returns the workers registered with the coordinator, oldest first, with
// their state (idle, busy, lost), current task and task counts, following the pages.
func (c *Client) ListWorkers(ctx context.Context) ([]*pb.WorkerInfo, error) {
	return pages.All(func(token string) ([]*pb.WorkerInfo, string, error) {
		resp, err := c.jobs.ListWorkers(ctx, &pb.ListWorkersRequest{PageSize: workersPage, PageToken: token})
		return resp.GetWorkers(), resp.GetNextPageToken(), fromRPC("list workers", err)
	})
}

// Cancel cancels the job.
func (c *Client) Cancel(ctx context.Context, jobID string) (*pb.Job, error) {
	resp, err := c.jobs.CancelJob(ctx, &pb.CancelJobRequest{JobId: jobID})
	if err != nil {
		return nil, fromRPC("cancel job", err)
	}
	return resp.GetJob(), nil
}

// Requeue reopens a failed or cancelled job where it stopped (RequeueJob).
func (c *Client) Requeue(ctx context.Context, jobID string) (*pb.Job, error) {
	resp, err := c.jobs.RequeueJob(ctx, &pb.RequeueJobRequest{JobId: jobID})
	if err != nil {
		return nil, fromRPC("requeue job", err)
	}
	return resp.GetJob(), nil
}

// RetryTask queues a failed task again and reopens its job; it returns the job and the
// task.
func (c *Client) RetryTask(ctx context.Context, taskID string) (*pb.Job, *pb.Task, error) {
	resp, err := c.jobs.RetryTask(ctx, &pb.RetryTaskRequest{TaskId: taskID})
	if err != nil {
		return nil, nil, fromRPC("retry task", err)
	}
	return resp.GetJob(), resp.GetTask(), nil
}

// Delete deletes the job (cancelling it if it has not ended) and returns it as it was
// deleted.
func (c *Client) Delete(ctx context.Context, jobID string) (*pb.Job, error) {
	resp, err := c.jobs.DeleteJob(ctx, &pb.DeleteJobRequest{JobId: jobID})
	if err != nil {
		return nil, fromRPC("delete job", err)
	}
	return resp.GetJob(), nil
}

// JobEnded reports whether a job in state s has ended.
func JobEnded(s pb.JobState) bool {
	return s == pb.JobState_JOB_STATE_SUCCEEDED || s == pb.JobState_JOB_STATE_FAILED ||
		s == pb.JobState_JOB_STATE_CANCELLED
}

// watchResumeFor is how long Watch keeps trying to reopen a stream that a coordinator
// going away cut (UNAVAILABLE), counted from when it last saw the job change: long enough
// for a restarted coordinator to come back, or for the call to find another replica.
const watchResumeFor = 30 * time.Second

// Watch follows the job's events until it ends, calling fn (if not nil) for each event,
// the initial snapshot included, and returns the job as it ended. A stream that told of
// the job and was then cut because the coordinator went away is reopened (on another
// replica, for a client of several) for up to 30 s from the last change it saw in the
// job; fn then sees the new stream's snapshot, which carries the job as it stands. It
// returns an error if ctx ends first, or the stream breaks for another reason or cannot
// be reopened in time.
func (c *Client) Watch(ctx context.Context, jobID string, fn func(*pb.WatchJobResponse)) (*pb.Job, error) {
	var changed time.Time // zero until the first event: a farm never reached fails at once
	var last *pb.Job
	for pause := 100 * time.Millisecond; ; pause = min(2*pause, 2*time.Second) {
		job, err := c.watchOnce(ctx, jobID, fn)
		if job != nil && !proto.Equal(job, last) {
			last, changed, pause = job, time.Now(), 100*time.Millisecond
		}
		var e *Error
		if err == nil || !errors.As(err, &e) || e.Code != codes.Unavailable || changed.IsZero() || time.Since(changed) > c.watchResumeFor {
			return last, err
		}
		select {
		case <-ctx.Done():
			return last, ctx.Err()
		case <-time.After(pause):
		}
	}
}

// watchOnce is one WatchJob stream: the last job it told of, and nil once the job has
// ended.
func (c *Client) watchOnce(ctx context.Context, jobID string, fn func(*pb.WatchJobResponse)) (*pb.Job, error) {
	ctx, cancel := context.WithCancel(ctx)
	defer cancel()
	stream, err := c.jobs.WatchJob(ctx, &pb.WatchJobRequest{JobId: jobID})
	if err != nil {
		return nil, fromRPC("watch job", err)
	}
	var last *pb.Job
	for {
		ev, err := stream.Recv()
		if errors.Is(err, io.EOF) {
			if last == nil || !JobEnded(last.GetState()) {
				return last, &Error{Code: codes.Unavailable, Message: "watch job " + jobID + ": the event stream ended before the job did"}
			}
			return last, nil
		}
		if err != nil {
			return last, fromRPC("watch job", err)
		}
		if ev.GetJob() != nil {
			last = ev.GetJob()
		}
		if fn != nil {
			fn(ev)
		}
		if last != nil && JobEnded(last.GetState()) {
			return last, nil
		}
	}
}

// Output file names. Fetch writes a job's artifacts as BASE.exr (the final "image.exr")
// and BASE.png (the "preview.png"); any other artifact NAME as BASE.NAME. FetchAs takes
// BASE from its caller (farm render uses the scene file's name, so scenes/cornell-box.json
// gives out/cornell-box.exr); Fetch uses the job's display name (the scene's name field)
// made safe for a file name, or the job id if that is empty.
func outputFileName(base, artifact string) string {
	switch artifact {
	case "image.exr":
		return base + ".exr"
	case "preview.png":
		return base + ".png"
	}
	return base + "." + SafeFileName(artifact)
}

// SafeFileName turns free text (a scene name) into a file name: letters, digits, '.', '-'
// and '_' are kept, runs of anything else become one '-'. It returns "" if nothing usable
// is left.
func SafeFileName(s string) string {
	var b strings.Builder
	dash := false
	for _, r := range s {
		ok := r == '.' || r == '-' || r == '_' || (r >= 'a' && r <= 'z') || (r >= 'A' && r <= 'Z') || (r >= '0' && r <= '9')
		if ok {
			b.WriteRune(r)
			dash = false
		} else if !dash {
			b.WriteByte('-')
			dash = true
		}
	}
	out := strings.Trim(b.String(), "-.")
	if len(out) > 128 {
		out = out[:128]
	}
	return out
}

// Fetch downloads the outputs of a succeeded job into outDir (created if missing), named
// after the job's display name (see outputFileName), and returns the paths written.
func (c *Client) Fetch(ctx context.Context, jobID, outDir string) ([]string, error) {
	return c.FetchAs(ctx, jobID, outDir, "")
}

// FetchAs is Fetch with the base name of the files chosen by the caller; "" means the
// job's display name, or its id.
func (c *Client) FetchAs(ctx context.Context, jobID, outDir, base string) ([]string, error) {
	job, err := c.GetJob(ctx, jobID)
	if err != nil {
		return nil, err
	}
	if job.GetState() != pb.JobState_JOB_STATE_SUCCEEDED {
		return nil, &Error{Code: codes.FailedPrecondition,
			Message: fmt.Sprintf("job %s has no outputs: it is %s", jobID, tasks.JobStateName(job.GetState()))}
	}
	if base == "" {
		base = SafeFileName(job.GetDisplayName())
	}
	if base == "" {
		base = SafeFileName(job.GetId())
	}
	if len(job.GetOutputs()) == 0 {
		return nil, fmt.Errorf("job %s succeeded without outputs", jobID)
	}
	if err := os.MkdirAll(outDir, 0o755); err != nil {
		return nil, err
	}
	var paths []string
	for _, a := range job.GetOutputs() {
		path := filepath.Join(outDir, outputFileName(base, a.GetName()))
		if err := c.downloadFile(ctx, a, path); err != nil {
			return paths, err
		}
		paths = append(paths, path)
	}
	return paths, nil
}

// downloadFile writes artifact a to path, through a temporary file in the same folder
// that replaces path only once the bytes are complete and verified.
func (c *Client) downloadFile(ctx context.Context, a *pb.Artifact, path string) error {
	tmp, err := os.CreateTemp(filepath.Dir(path), "."+filepath.Base(path)+".*.part")
	if err != nil {
		return err
	}
	defer os.Remove(tmp.Name()) // no-op after the rename
	n, err := c.Download(ctx, a.GetDigest(), tmp)
	if cerr := tmp.Close(); err == nil {
		err = cerr
	}
	if err == nil && a.GetSizeBytes() != 0 && n != a.GetSizeBytes() {
		err = fmt.Errorf("download %s: got %d bytes, the job says %d", a.GetName(), n, a.GetSizeBytes())
	}
	if err != nil {
		return fmt.Errorf("fetch %s: %w", a.GetName(), err)
	}
	if err := os.Chmod(tmp.Name(), 0o644); err != nil {
		return err
	}
	return os.Rename(tmp.Name(), path)
}

// RoundError is the error a round reports and what it is called: its RMSE against the
// reference if it has one ("reference RMSE"), else its "estimated error" (an estimate, and
// named so wherever it is shown); ok is false if it has neither.
func RoundError(r *pb.RoundReport) (label string, value float64, ok bool) {
	switch {
	case r.ReferenceRmse != nil:
		return "reference RMSE", r.GetReferenceRmse(), true
	case r.ErrorEstimate != nil:
		return "estimated error", r.GetErrorEstimate(), true
	}
	return "", 0, false
}
