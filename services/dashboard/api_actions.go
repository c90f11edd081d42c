package dashboard

import (
	"context"
	"encoding/json"
	"fmt"
	"io"
	"math"
	"net/http"
	"strings"

	pb "photonfarm/proto/renderfarm/v1"
)

// submit queues the scene in the body (scenes/*.json's format) as a new job, with the
// files it names sent beside it (uploads.go) stored first.
func (s *Server) submit(w http.ResponseWriter, r *http.Request) {
	data, err := io.ReadAll(r.Body)
	if err != nil {
		s.writeError(w, r, err)
		return
	}
	sc, files, err := readSubmission(data)
	if err != nil {
		s.writeError(w, r, err)
		return
	}
	s.answer(w, r, func(ctx context.Context) (any, error) {
		if err := attachFiles(ctx, s.files, sc, files); err != nil {
			return nil, err
		}
		resp, err := s.jobs.SubmitJob(ctx, &pb.SubmitJobRequest{Scene: sc})
		if err != nil {
			return nil, err
		}
		s.log.Info("dashboard submitted a job", "job", resp.GetJob().GetId(), "name", resp.GetJob().GetDisplayName(), "files", len(files))
		return jobAnswer(resp, nil)
	})
}

// jobAnswer is the answer {"job": Job} of a call that returns a job.
func jobAnswer(resp interface{ GetJob() *pb.Job }, err error) (any, error) {
	if err != nil {
		return nil, err
	}
	return map[string]any{"job": pj(resp.GetJob())}, nil
}

// cancel cancels a job; 409 if it has ended.
func (s *Server) cancel(w http.ResponseWriter, r *http.Request) {
	s.answer(w, r, func(ctx context.Context) (any, error) {
		return jobAnswer(s.jobs.CancelJob(ctx, &pb.CancelJobRequest{JobId: r.PathValue("id")}))
	})
}

// requeue reopens a failed or cancelled job where it stopped; 409 for any other.
func (s *Server) requeue(w http.ResponseWriter, r *http.Request) {
	s.answer(w, r, func(ctx context.Context) (any, error) {
		return jobAnswer(s.jobs.RequeueJob(ctx, &pb.RequeueJobRequest{JobId: r.PathValue("id")}))
	})
}

// retry queues a failed task of the job again, reopening the job: {"job": Job, "task":
// Task}; 409 for a task that has not failed, 404 for a task not of that job.
func (s *Server) retry(w http.ResponseWriter, r *http.Request) {
	jobID, taskID := r.PathValue("id"), r.PathValue("task")
	if !strings.HasPrefix(taskID, jobID+".") { // task ids are "{job_id}.{index}"
		s.writeError(w, r, errorf(http.StatusNotFound, fmt.Sprintf("job %s has no task %q", jobID, taskID)))
		return
	}
	s.answer(w, r, func(ctx context.Context) (any, error) {
		resp, err := s.jobs.RetryTask(ctx, &pb.RetryTaskRequest{TaskId: taskID})
		if err != nil {
			return nil, err
		}
		return map[string]any{"job": pj(resp.GetJob()), "task": pj(resp.GetTask())}, nil
	})
}

// deleteJob deletes a job (cancelling it if it runs): {"job": Job} as it was deleted.
func (s *Server) deleteJob(w http.ResponseWriter, r *http.Request) {
	s.answer(w, r, func(ctx context.Context) (any, error) {
		resp, err := s.jobs.DeleteJob(ctx, &pb.DeleteJobRequest{JobId: r.PathValue("id")})
		if err == nil {
			s.log.Info("dashboard deleted a job", "job", resp.GetJob().GetId())
		}
		return jobAnswer(resp, err)
	})
}

// setPriority sets a job's priority from {"priority": N}; the coordinator checks the
// range.
func (s *Server) setPriority(w http.ResponseWriter, r *http.Request) {
	var body struct {
		Priority *json.Number `json:"priority"`
	}
	dec := json.NewDecoder(r.Body)
	dec.UseNumber()
	if err := dec.Decode(&body); err != nil {
		s.writeError(w, r, errorf(http.StatusBadRequest, "want a JSON body {\"priority\": N}: "+err.Error()))
		return
	}
	if body.Priority == nil {
		s.writeError(w, r, errorf(http.StatusBadRequest, "priority: missing"))
		return
	}
	p, err := body.Priority.Int64()
	if err != nil || p < math.MinInt32 || p > math.MaxInt32 {
		s.writeError(w, r, errorf(http.StatusBadRequest, fmt.Sprintf("priority: must be an integer in [-1000, 1000], got %s", body.Priority.String())))
		return
	}
	s.answer(w, r, func(ctx context.Context) (any, error) {
		return jobAnswer(s.jobs.SetJobPriority(ctx, &pb.SetJobPriorityRequest{JobId: r.PathValue("id"), Priority: int32(p)}))
	})
}

// unblock takes a worker off a job's blocklist from {"workerId": "w-..."}; an empty or
// missing workerId unblocks every worker of the job, as UnblockWorker does.
func (s *Server) unblock(w http.ResponseWriter, r *http.Request) {
	var body struct {
		WorkerID string `json:"workerId"`
	}
	if err := json.NewDecoder(r.Body).Decode(&body); err != nil {
		s.writeError(w, r, errorf(http.StatusBadRequest, "want a JSON body {\"workerId\": \"...\"}: "+err.Error()))
		return
	}
	s.answer(w, r, func(ctx context.Context) (any, error) {
		return jobAnswer(s.jobs.UnblockWorker(ctx, &pb.UnblockWorkerRequest{JobId: r.PathValue("id"), WorkerId: body.WorkerID}))
	})
}
