package dashboard

import (
	"context"
	"net/http"

	"photonfarm/client"
	pb "photonfarm/proto/renderfarm/v1"
)

// allJobs returns every job, newest first, following the pages.
func (s *Server) allJobs(ctx context.Context) ([]*pb.Job, error) { return client.AllJobs(ctx, s.jobs) }

// allTasks returns every task of a job in plan order, following the pages.
func (s *Server) allTasks(ctx context.Context, jobID string) ([]*pb.Task, error) {
	return client.AllTasks(ctx, s.jobs, jobID)
}

// jobWithTasks reads a job and its tasks: {"job": Job, "tasks": [Task...]}.
func (s *Server) jobWithTasks(ctx context.Context, jobID string) (map[string]any, error) {
	resp, err := s.jobs.GetJob(ctx, &pb.GetJobRequest{JobId: jobID})
	if err != nil {
		return nil, err
	}
	tasks, err := s.allTasks(ctx, jobID)
	if err != nil {
		return nil, err
	}
	return map[string]any{"job": pj(resp.GetJob()), "tasks": pjs(tasks)}, nil
}

// answer runs call with the request's token (for at most callTimeout) and writes what it
// returns as the JSON answer, or its error.
func (s *Server) answer(w http.ResponseWriter, r *http.Request, call func(ctx context.Context) (any, error)) {
	ctx, cancel := callCtx(r)
	defer cancel()
	body, err := call(ctx)
	if err != nil {
		s.writeError(w, r, err)
		return
	}
	writeJSON(w, http.StatusOK, body)
}

func (s *Server) listJobs(w http.ResponseWriter, r *http.Request) {
	s.answer(w, r, func(ctx context.Context) (any, error) {
		jobs, err := s.allJobs(ctx)
		if err != nil {
			return nil, err
		}
		return map[string]any{"jobs": pjs(jobs)}, nil
	})
}

func (s *Server) getJob(w http.ResponseWriter, r *http.Request) {
	s.answer(w, r, func(ctx context.Context) (any, error) { return s.jobWithTasks(ctx, r.PathValue("id")) })
}

// WorkersPage is how many workers a page of /api/workers (and the workers event) holds.
const WorkersPage = 500

// workersPage reads the page of workers token names ("" for the first):
// {"workers": [WorkerInfo...], "nextPageToken": "..."} ("" on the last page).
func (s *Server) workersPage(ctx context.Context, token string) (map[string]any, error) {
	resp, err := s.jobs.ListWorkers(ctx, &pb.ListWorkersRequest{PageSize: WorkersPage, PageToken: token})
	if err != nil {
		return nil, err
	}
	return map[string]any{"workers": pjs(resp.GetWorkers()), "nextPageToken": resp.GetNextPageToken()}, nil
}

func (s *Server) listWorkers(w http.ResponseWriter, r *http.Request) {
	s.answer(w, r, func(ctx context.Context) (any, error) { return s.workersPage(ctx, r.URL.Query().Get("pageToken")) })
}
