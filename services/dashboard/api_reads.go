package dashboard

import (
	"context"
	"net/http"

	"photonfarm/client"
	pb "photonfarm/proto/renderfarm/v1"
)

// allJobs returns every job, newest first, following the pages.
func (s *Server) allJobs(ctx context.Context) ([]*pb.Job, error) { return client.AllJobs(ctx, s.jobs) }

// TasksPage is how many tasks a page of /api/jobs/{id}/tasks (and the first page sent
// with a job) holds: the rows the job page's table adds at a time. A job may have about
// 95,000 tasks a round; the dashboard never reads them all for one answer.
const TasksPage = 500

// tasksPage reads the page of a job's tasks, in plan order, that token names ("" for the
// first): {"tasks": [Task...], "nextPageToken": "..."} ("" on the last page).
func (s *Server) tasksPage(ctx context.Context, jobID, token string) (map[string]any, error) {
	resp, err := s.jobs.ListTasks(ctx, &pb.ListTasksRequest{JobId: jobID, PageSize: TasksPage, PageToken: token})
	if err != nil {
		return nil, err
	}
	return map[string]any{"tasks": pjs(resp.GetTasks()), "nextPageToken": resp.GetNextPageToken()}, nil
}

// withFirstTasks is {"job": job, "tasks": [the first page], "nextPageToken": "..."}.
func (s *Server) withFirstTasks(ctx context.Context, job *pb.Job) (map[string]any, error) {
	page, err := s.tasksPage(ctx, job.GetId(), "")
	if err != nil {
		return nil, err
	}
	page["job"] = pj(job)
	return page, nil
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
	s.answer(w, r, func(ctx context.Context) (any, error) {
		resp, err := s.jobs.GetJob(ctx, &pb.GetJobRequest{JobId: r.PathValue("id")})
		if err != nil {
			return nil, err
		}
		return s.withFirstTasks(ctx, resp.GetJob())
	})
}

func (s *Server) listTasks(w http.ResponseWriter, r *http.Request) {
	s.answer(w, r, func(ctx context.Context) (any, error) {
		return s.tasksPage(ctx, r.PathValue("id"), r.URL.Query().Get("pageToken"))
	})
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
