package dashboard

import (
	"context"
	"encoding/json"
	"fmt"
	"io"
	"math"
	"net/http"
	"strings"

	"photonfarm/contract/scene"
	pb "photonfarm/proto/renderfarm/v1"
)

// submit queues the scene JSON in the body (scenes/*.json's format, meshes inline) as a
// new job.
func (s *Server) submit(w http.ResponseWriter, r *http.Request) {
	data, err := io.ReadAll(r.Body)
	if err != nil {
		s.writeError(w, r, err)
		return
	}
	sc, err := scene.ParseJSON(data)
	if err != nil {
		s.writeError(w, r, errorf(http.StatusBadRequest, "not a scene file: "+err.Error()))
		return
	}
	if why := fileByPath(sc); why != "" {
		s.writeError(w, r, errorf(http.StatusBadRequest, why))
		return
	}
	s.answer(w, r, func(ctx context.Context) (any, error) {
		resp, err := s.jobs.SubmitJob(ctx, &pb.SubmitJobRequest{Scene: sc})
		if err != nil {
			return nil, err
		}
		s.log.Info("dashboard submitted a job", "job", resp.GetJob().GetId(), "name", resp.GetJob().GetDisplayName())
		return jobAnswer(resp, nil)
	})
}

// fileByPath says why a scene that names a file by path cannot be submitted from a
// browser, or "" if it names none: the browser sends the scene alone, so there is nothing
// to upload the file from.
func fileByPath(sc *pb.Scene) string {
	const how = "the dashboard cannot upload files from the browser: put the mesh inline as \"triangles\", or submit the scene with farm submit"
	for i, sh := range sc.GetShapes() {
		if m := sh.GetMesh(); m.GetPath() != "" && m.GetDigest() == "" {
			return fmt.Sprintf("shapes[%d].mesh names the file %s, but %s", i, m.GetPath(), how)
		}
	}
	if p := sc.GetProgressive().GetReference().GetPath(); p != "" && sc.GetProgressive().GetReference().GetDigest() == "" {
		return fmt.Sprintf("progressive.reference names the image %s, but the dashboard cannot upload files from the browser: submit the scene with farm submit", p)
	}
	return ""
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
