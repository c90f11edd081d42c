package dashboard

import (
	"context"
	"encoding/json"
	"errors"
	"fmt"
	"io"
	"net/http"
	"sync"
	"time"

	"google.golang.org/protobuf/proto"

	"photonfarm/client"
	pb "photonfarm/proto/renderfarm/v1"
)

// sse writes server-sent events.
type sse struct {
	w http.ResponseWriter
	f *http.ResponseController
}

// event is one server-sent event: its name and the value its JSON data encodes.
type event struct {
	name string
	data any
}

// startSSE takes a stream slot, writes the event-stream headers and sends the first
// events (read before the stream starts, so that a failed read is still an HTTP error).
// It answers 503 and returns false when MaxStreams are open, and returns false, the slot
// given back, when the first events cannot be sent; otherwise release gives the slot back.
func (s *Server) startSSE(w http.ResponseWriter, r *http.Request, first ...event) (out *sse, release func(), ok bool) {
	select {
	case s.streams <- struct{}{}:
	default:
		s.writeError(w, r, errorf(http.StatusServiceUnavailable, "too many event streams open; try again later"))
		return nil, nil, false
	}
	release = func() { <-s.streams }
	h := w.Header()
	h.Set("Content-Type", "text/event-stream")
	h.Set("Cache-Control", "no-store")
	h.Set("X-Accel-Buffering", "no") // nginx: do not buffer the stream
	w.WriteHeader(http.StatusOK)
	rc := http.NewResponseController(w)
	// The server's write timeout (if any) must not end a long-lived stream.
	_ = rc.SetWriteDeadline(time.Time{})
	out = &sse{w: w, f: rc}
	for _, ev := range first {
		if out.send(ev.name, ev.data) != nil {
			release()
			return nil, nil, false
		}
	}
	return out, release, true
}

// send writes one event with v as its JSON data and flushes it.
func (e *sse) send(event string, v any) error {
	b, err := json.Marshal(v)
	if err != nil {
		return err
	}
	// JSON from encoding/json has no raw newlines, so the data fits one data: line.
	if _, err := fmt.Fprintf(e.w, "event: %s\ndata: %s\n\n", event, b); err != nil {
		return err
	}
	return e.f.Flush()
}

// ping writes a comment, which keeps proxies from closing an idle stream.
func (e *sse) ping() error {
	if _, err := io.WriteString(e.w, ": ping\n\n"); err != nil {
		return err
	}
	return e.f.Flush()
}

// farmEvents streams the job list: all of it on connect, then the jobs that changed (a
// job feed shared by the streams of one token polls the list every JobsPoll, so at most
// once per poll), and the first page of workers every WorkersEvery. A refused or failed
// call ends the stream; the browser's EventSource reconnects and then gets the HTTP error.
func (s *Server) farmEvents(w http.ResponseWriter, r *http.Request) {
	token := tokenOf(r)
	ctx := client.ContextWithToken(r.Context(), token)
	// The first reads happen before the stream starts, so that a bad token is a 401.
	sub, jobs, err := s.jobFeeds.subscribe(ctx, token)
	if err != nil {
		s.writeError(w, r, err)
		return
	}
	defer sub.leave()
	workers, err := s.pollWorkers(ctx)
	if err != nil {
		s.writeError(w, r, err)
		return
	}
	out, release, ok := s.startSSE(w, r, event{"jobs", map[string]any{"jobs": pjs(jobs)}}, event{"workers", workers})
	if !ok {
		return
	}
	defer release()
	workerTick := time.NewTicker(s.cfg.WorkersEvery)
	defer workerTick.Stop()
	ping := time.NewTicker(s.cfg.PingEvery)
	defer ping.Stop()
	for {
		var err error
		select {
		case <-ctx.Done():
			return
		case <-sub.wake:
			changed, removed, ferr := sub.take()
			if err = ferr; err == nil && len(changed)+len(removed) > 0 {
				err = out.send("jobs-changed", map[string]any{"jobs": pjs(changed), "removed": append([]string{}, removed...)})
			}
		case <-workerTick.C:
			if workers, err = s.pollWorkers(ctx); err == nil {
				err = out.send("workers", workers)
			}
		case <-ping.C:
			err = out.ping()
		}
		if err != nil {
			if ctx.Err() == nil {
				s.log.Info("dashboard event stream ended", "err", err)
			}
			return
		}
	}
}

func (s *Server) pollJobs(ctx context.Context) ([]*pb.Job, error) {
	ctx, cancel := context.WithTimeout(ctx, callTimeout)
	defer cancel()
	return s.allJobs(ctx)
}

// pollWorkers reads the first page of workers (workersPage).
func (s *Server) pollWorkers(ctx context.Context) (map[string]any, error) {
	ctx, cancel := context.WithTimeout(ctx, callTimeout)
	defer cancel()
	return s.workersPage(ctx, "")
}

// jobUpdates coalesces a job's WatchJob events between two sends: the latest job, the
// latest state of each task changed (in the order they first changed), and whether the
// whole job must be sent again.
type jobUpdates struct {
	mu     sync.Mutex
	job    *pb.Job
	tasks  map[string]*pb.Task
	order  []string
	resync bool  // a change no task event shows: a new round's tasks
	done   bool  // the watch ended
	err    error // why it ended (io.EOF after the job ended)
	wake   chan struct{}
}

func (u *jobUpdates) add(ev *pb.WatchJobResponse) {
	u.mu.Lock()
	defer u.mu.Unlock()
	if j := ev.GetJob(); j != nil {
		if u.job != nil && len(j.GetRounds()) != len(u.job.GetRounds()) {
			u.resync = true // the next round's tasks were added, without events of their own
		}
		u.job = j
	}
	if t := ev.GetTask(); t != nil {
		if _, ok := u.tasks[t.GetId()]; !ok {
			u.order = append(u.order, t.GetId())
		}
		u.tasks[t.GetId()] = t
	}
	u.signal()
}

func (u *jobUpdates) finish(err error) {
	u.mu.Lock()
	defer u.mu.Unlock()
	u.done, u.err = true, err
	u.signal()
}

func (u *jobUpdates) signal() {
	select {
	case u.wake <- struct{}{}:
	default:
	}
}

// take returns what changed since the last take and clears it.
func (u *jobUpdates) take() (job *pb.Job, tasks []*pb.Task, resync, done bool, err error) {
	u.mu.Lock()
	defer u.mu.Unlock()
	for _, id := range u.order {
		tasks = append(tasks, u.tasks[id])
	}
	job, resync, done, err = u.job, u.resync, u.done, u.err
	clear(u.tasks)
	u.order, u.resync = u.order[:0], false
	return job, tasks, resync, done, err
}

// jobEvents streams one job: the whole job on connect, then its changed tasks at most
// every JobUpdateEvery (each task's latest state, one task event each), the whole job
// again when something changed that task events do not show (a new round's tasks, a
// change of the job alone), and the end.
func (s *Server) jobEvents(w http.ResponseWriter, r *http.Request) {
	jobID := r.PathValue("id")
	ctx, cancel := context.WithCancel(client.ContextWithToken(r.Context(), tokenOf(r)))
	defer cancel()
	watch, err := s.jobs.WatchJob(ctx, &pb.WatchJobRequest{JobId: jobID})
	if err != nil {
		s.writeError(w, r, err)
		return
	}
	// The snapshot comes first; an unknown job or a refused token fails here, before
	// the stream starts.
	snap, err := watch.Recv()
	if err != nil {
		if errors.Is(err, io.EOF) {
			err = errorf(http.StatusBadGateway, "the coordinator ended the watch at once")
		}
		s.writeError(w, r, err)
		return
	}
	job := snap.GetJob()
	first, err := s.jobPage(ctx, job)
	if err != nil {
		s.writeError(w, r, err)
		return
	}
	out, release, ok := s.startSSE(w, r, event{"job", first})
	if !ok {
		return
	}
	defer release()
	if jobEnded(job) {
		out.send("end", map[string]any{"job": pj(job)})
		return
	}

	u := &jobUpdates{job: job, tasks: map[string]*pb.Task{}, wake: make(chan struct{}, 1)}
	go func() {
		for {
			ev, err := watch.Recv()
			if err != nil {
				u.finish(err)
				return
			}
			u.add(ev)
		}
	}()
	ping := time.NewTicker(s.cfg.PingEvery)
	defer ping.Stop()
	var last time.Time
	sent := job // the job as the browser last saw it
	for {
		select {
		case <-ctx.Done():
			return
		case <-ping.C:
			if out.ping() != nil {
				return
			}
			continue
		case <-u.wake:
		}
		// At most one update per JobUpdateEvery: wait out the rest of the interval,
		// gathering what else changes meanwhile.
		if wait := s.cfg.JobUpdateEvery - time.Since(last); wait > 0 {
			select {
			case <-ctx.Done():
				return
			case <-time.After(wait):
			}
		}
		last = time.Now()
		job, changed, resync, done, werr := u.take()
		if len(changed) == 0 && !proto.Equal(job, sent) {
			resync = true
		}
		if resync && !jobEnded(job) {
			page, err := s.jobPage(ctx, job)
			if err != nil {
				return
			}
			if out.send("job", page) != nil {
				return
			}
			sent = job
		} else {
			for _, t := range changed {
				if out.send("task", map[string]any{"job": pj(job), "task": pj(t)}) != nil {
					return
				}
				sent = job
			}
		}
		if jobEnded(job) {
			out.send("end", map[string]any{"job": pj(job)})
			return
		}
		if done {
			// The watch broke before the job ended (the coordinator stopped): end the
			// stream; the browser reconnects.
			if ctx.Err() == nil {
				s.log.Info("dashboard job stream ended", "job", jobID, "err", werr)
			}
			return
		}
	}
}

// jobPage is the job event's data: the job and the first page of its tasks.
func (s *Server) jobPage(ctx context.Context, job *pb.Job) (map[string]any, error) {
	ctx, cancel := context.WithTimeout(ctx, callTimeout)
	defer cancel()
	return s.withFirstTasks(ctx, job)
}

func jobEnded(j *pb.Job) bool {
	switch j.GetState() {
	case pb.JobState_JOB_STATE_SUCCEEDED, pb.JobState_JOB_STATE_FAILED, pb.JobState_JOB_STATE_CANCELLED:
		return true
	}
	return false
}
