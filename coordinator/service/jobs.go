package service

import (
	"bytes"
	"context"
	"time"

	"google.golang.org/protobuf/proto"
	"google.golang.org/protobuf/types/known/timestamppb"

	"photonfarm/contract/scene"
	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/planner"
	"photonfarm/coordinator/retention"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// Page sizes of the list RPCs (job.proto).
const (
	DefaultJobsPage  = 50
	MaxJobsPage      = 1000
	DefaultTasksPage = 500
	MaxTasksPage     = 10000
)

type jobServer struct {
	pb.UnimplementedJobServiceServer
	s *Service
}

var _ pb.JobServiceServer = (*jobServer)(nil)

// MaxIDLength bounds every id a request names (job, task, worker, request ids).
const MaxIDLength = 128

// checkID refuses an empty id, and one no id of ours could be: too long, or with spaces or
// control characters (the value is not echoed, since it may be huge or unprintable).
func checkID(field, v string) error {
	if v == "" {
		return errs.Field(field, "must be non-empty")
	}
	return checkToken(field, v)
}

// checkToken refuses ids (that may be empty) longer than MaxIDLength bytes or with bytes
// outside printable ASCII.
func checkToken(field, v string) error {
	if len(v) > MaxIDLength {
		return errs.Field(field, "must be at most %d bytes, got %d", MaxIDLength, len(v))
	}
	for i := 0; i < len(v); i++ {
		if v[i] <= ' ' || v[i] > '~' {
			return errs.Field(field, "must be printable ASCII without spaces (byte %d is 0x%02x)", i, v[i])
		}
	}
	return nil
}

func pageSize(field string, n int32, def, max int) (int, error) {
	switch {
	case n < 0:
		return 0, errs.Field(field, "must be >= 0, got %d", n)
	case n == 0:
		return def, nil
	case int(n) > max:
		return max, nil
	}
	return int(n), nil
}

// SubmitJob validates the scene, checks that the files it names are in the blob store and
// that the files it names pass their checks (checkFiles), stores the scene (defaults filled in) as a blob,
// plans it and creates the job. Nothing is stored for a bad scene.
func (j *jobServer) SubmitJob(ctx context.Context, req *pb.SubmitJobRequest) (*pb.SubmitJobResponse, error) {
	s := j.s
	sc := req.GetScene()
	if sc == nil {
		return nil, errs.Field("scene", "missing")
	}
	if err := checkToken("request_id", req.GetRequestId()); err != nil {
		return nil, err
	}
	if err := store.CheckPriority(req.GetPriority()); err != nil {
		return nil, err
	}
	if err := scene.Validate(sc); err != nil {
		return nil, err
	}
	if err := s.checkInputBlobs(ctx, sc); err != nil {
		return nil, err
	}
	if err := s.checkFiles(ctx, sc); err != nil {
		return nil, err
	}
	sc = scene.Defaults(sc)
	data, err := proto.MarshalOptions{Deterministic: true}.Marshal(sc)
	if err != nil {
		return nil, errs.Wrap(errs.Internal, err, "marshal scene")
	}
	info, err := s.cfg.Blobs.Put(ctx, bytes.NewReader(data), int64(len(data)), "")
	if err != nil {
		return nil, err
	}
	tasks := planner.Plan(sc)
	job, err := s.cfg.Store.CreateJob(ctx, store.NewJob{
		Plan:        planner.Passes(sc),
		DisplayName: sc.GetName(),
		SceneDigest: info.Digest,
		Width:       sc.GetFilm().GetWidth(),
		Height:      sc.GetFilm().GetHeight(),
		Tasks:       tasks,
		RequestID:   req.GetRequestId(),
		Priority:    req.GetPriority(),
	})
	if err != nil {
		return nil, err
	}
	s.cfg.Metrics.JobSubmitted()
	s.log.Info("job submitted", "job", job.GetId(), "name", job.GetDisplayName(), "priority", job.GetPriority(),
		"width", job.GetWidth(), "height", job.GetHeight(), "tasks", len(tasks), "scene", info.Digest)
	s.queued.broadcast()
	return &pb.SubmitJobResponse{Job: job}, nil
}

// checkInputBlobs checks that the blobs a scene names (scene.Files: mesh files and parts,
// textures, the reference image) exist, touching each (blobstore.Touch) so that the
// collector of unreferenced blobs, which may not see the job yet, keeps them.
func (s *Service) checkInputBlobs(ctx context.Context, sc *pb.Scene) error {
	for _, f := range scene.Files(sc) {
		if _, err := s.cfg.Blobs.Touch(ctx, f.Digest); err != nil {
			if errs.Is(err, errs.NotFound) {
				return errs.Field(f.Field+".digest", "no blob %s in the blob store; upload the file first", f.Digest)
			}
			return err
		}
	}
	return nil
}

// PlanScene validates and plans a scene as SubmitJob would, without storing anything. The
// meshes already in the blob store are checked; planning does not need the others, so a
// client may plan before uploading.
func (j *jobServer) PlanScene(ctx context.Context, req *pb.PlanSceneRequest) (*pb.PlanSceneResponse, error) {
	sc := req.GetScene()
	if sc == nil {
		return nil, errs.Field("scene", "missing")
	}
	if err := scene.Validate(sc); err != nil {
		return nil, err
	}
	if err := j.s.checkFiles(ctx, sc); err != nil {
		return nil, err
	}
	sc = scene.Defaults(sc)
	return &pb.PlanSceneResponse{Plan: planner.Passes(sc), Phases: planner.PhaseCounts(planner.Plan(sc))}, nil
}

func (j *jobServer) GetJob(ctx context.Context, req *pb.GetJobRequest) (*pb.GetJobResponse, error) {
	if err := checkID("job_id", req.GetJobId()); err != nil {
		return nil, err
	}
	job, err := j.s.cfg.Store.GetJob(ctx, req.GetJobId())
	if err != nil {
		return nil, err
	}
	return &pb.GetJobResponse{Job: job}, nil
}

func (j *jobServer) ListJobs(ctx context.Context, req *pb.ListJobsRequest) (*pb.ListJobsResponse, error) {
	n, err := pageSize("page_size", req.GetPageSize(), DefaultJobsPage, MaxJobsPage)
	if err != nil {
		return nil, err
	}
	jobs, next, err := j.s.cfg.Store.ListJobs(ctx, n, req.GetPageToken())
	if err != nil {
		return nil, err
	}
	return &pb.ListJobsResponse{Jobs: jobs, NextPageToken: next}, nil
}

func (j *jobServer) ListTasks(ctx context.Context, req *pb.ListTasksRequest) (*pb.ListTasksResponse, error) {
	if err := checkID("job_id", req.GetJobId()); err != nil {
		return nil, err
	}
	n, err := pageSize("page_size", req.GetPageSize(), DefaultTasksPage, MaxTasksPage)
	if err != nil {
		return nil, err
	}
	tasks, next, err := j.s.cfg.Store.ListTasks(ctx, req.GetJobId(), n, req.GetPageToken())
	if err != nil {
		return nil, err
	}
	return &pb.ListTasksResponse{Tasks: tasks, NextPageToken: next}, nil
}

func (j *jobServer) CancelJob(ctx context.Context, req *pb.CancelJobRequest) (*pb.CancelJobResponse, error) {
	if err := checkID("job_id", req.GetJobId()); err != nil {
		return nil, err
	}
	c, err := j.s.cfg.Store.CancelJob(ctx, req.GetJobId())
	if err != nil {
		return nil, err
	}
	j.s.publish(c)
	return &pb.CancelJobResponse{Job: c.Job}, nil
}

func (j *jobServer) SetJobPriority(ctx context.Context, req *pb.SetJobPriorityRequest) (*pb.SetJobPriorityResponse, error) {
	if err := checkID("job_id", req.GetJobId()); err != nil {
		return nil, err
	}
	if err := store.CheckPriority(req.GetPriority()); err != nil {
		return nil, err
	}
	c, err := j.s.cfg.Store.SetJobPriority(ctx, req.GetJobId(), req.GetPriority())
	if err != nil {
		return nil, err
	}
	j.s.log.Info("job priority set", "job", req.GetJobId(), "priority", req.GetPriority())
	j.s.publish(c)
	return &pb.SetJobPriorityResponse{Job: c.Job}, nil
}

// UnblockWorker takes a worker (or all, for an empty worker_id) off a job's blocklist and
// wakes waiting workers, since the job's tasks may now be theirs.
func (j *jobServer) UnblockWorker(ctx context.Context, req *pb.UnblockWorkerRequest) (*pb.UnblockWorkerResponse, error) {
	if err := checkID("job_id", req.GetJobId()); err != nil {
		return nil, err
	}
	if err := checkToken("worker_id", req.GetWorkerId()); err != nil {
		return nil, err
	}
	c, err := j.s.cfg.Store.UnblockWorker(ctx, req.GetJobId(), req.GetWorkerId())
	if err != nil {
		return nil, err
	}
	if c.Queued {
		j.s.log.Info("worker unblocked", "job", req.GetJobId(), "worker", req.GetWorkerId())
	}
	j.s.publish(c)
	return &pb.UnblockWorkerResponse{Job: c.Job}, nil
}

// RequeueJob reopens a failed or cancelled job where it stopped and wakes waiting workers.
func (j *jobServer) RequeueJob(ctx context.Context, req *pb.RequeueJobRequest) (*pb.RequeueJobResponse, error) {
	if err := checkID("job_id", req.GetJobId()); err != nil {
		return nil, err
	}
	c, err := j.s.cfg.Store.ReopenJob(ctx, req.GetJobId(), "")
	if err != nil {
		return nil, err
	}
	j.s.log.Info("job requeued", "job", req.GetJobId())
	j.s.publish(c)
	return &pb.RequeueJobResponse{Job: c.Job}, nil
}

// RetryTask queues a failed task again, reopening its job.
func (j *jobServer) RetryTask(ctx context.Context, req *pb.RetryTaskRequest) (*pb.RetryTaskResponse, error) {
	if err := checkID("task_id", req.GetTaskId()); err != nil {
		return nil, err
	}
	jobID, ok := store.JobOfTask(req.GetTaskId())
	if !ok {
		return nil, errs.Field("task_id", "is not a task id: want {job_id}.{index}, as the job's task list names them")
	}
	c, err := j.s.cfg.Store.ReopenJob(ctx, jobID, req.GetTaskId())
	if err != nil {
		return nil, err
	}
	j.s.log.Info("task retried", "task", req.GetTaskId(), "job", jobID)
	j.s.publish(c)
	return &pb.RetryTaskResponse{Job: c.Job, Task: c.Task}, nil
}

// DeletePurgeSteps bounds the PurgeJobs steps DeleteJob runs (each of
// retention.PurgeBudget task records): a larger job is finished by the next sweep.
const DeletePurgeSteps = 64

// DeleteJob cancels a job that has not ended and deletes it: gone for every read at once,
// its records deleted by purge steps run now. Its blobs are left to the blob collection
// (retention), since another job may share them.
func (j *jobServer) DeleteJob(ctx context.Context, req *pb.DeleteJobRequest) (*pb.DeleteJobResponse, error) {
	if err := checkID("job_id", req.GetJobId()); err != nil {
		return nil, err
	}
	c, err := j.s.cfg.Store.DeleteJob(ctx, req.GetJobId())
	if err != nil {
		return nil, err
	}
	j.s.log.Info("job deleted", "job", req.GetJobId(), "state", c.Job.GetState().String())
	j.s.publish(c)
	for range DeletePurgeSteps {
		// No cutoffs: only the jobs marked deleted are purged.
		p, err := j.s.cfg.Store.PurgeJobs(ctx, time.Time{}, time.Time{}, retention.PurgeBudget)
		if err != nil {
			j.s.log.Warn("purge after a delete failed; the next sweep finishes it", "job", req.GetJobId(), "err", err)
			break
		}
		if !p.More {
			break
		}
	}
	return &pb.DeleteJobResponse{Job: c.Job}, nil
}

// WatchJob sends a snapshot, then every event of the job, and returns after the event
// that carries its final state.
func (j *jobServer) WatchJob(req *pb.WatchJobRequest, stream pb.JobService_WatchJobServer) error {
	s := j.s
	ctx := stream.Context()
	if err := checkID("job_id", req.GetJobId()); err != nil {
		return err
	}
	// Subscribe before reading the snapshot so that no change falls in between.
	w := s.cfg.Events.Watch(req.GetJobId())
	defer w.Close()
	job, err := s.cfg.Store.GetJob(ctx, req.GetJobId())
	if err != nil {
		return err
	}
	snap := &pb.WatchJobResponse{Kind: pb.JobEventKind_JOB_EVENT_KIND_SNAPSHOT, Time: timestamppb.New(s.cfg.Clock.Now()), Job: job}
	if err := stream.Send(snap); err != nil {
		return err
	}
	if store.Ended(job.GetState()) {
		return nil
	}
	ctx, cancel := context.WithCancel(ctx)
	defer cancel()
	go func() {
		select {
		case <-s.done:
			cancel()
		case <-ctx.Done():
		}
	}()
	for {
		ev, err := w.Next(ctx)
		if err != nil {
			select {
			case <-s.done:
				return errs.E(errs.Unavailable, "coordinator shutting down")
			default:
				return err
			}
		}
		if err := stream.Send(ev); err != nil {
			return err
		}
		if ev.GetKind() == pb.JobEventKind_JOB_EVENT_KIND_STATE_CHANGED && store.Ended(ev.GetJob().GetState()) {
			return nil
		}
	}
}
