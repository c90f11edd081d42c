// Package memstore is the in-process store.Store: all state in maps behind one mutex, so
// every method is trivially atomic. It is the embedded default (one-machine farms, unit
// tests); state is lost when the process exits.
package memstore

import (
	"context"
	"fmt"
	"sync"
	"time"

	"google.golang.org/protobuf/proto"
	"google.golang.org/protobuf/types/known/timestamppb"

	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// Store is an in-memory store.Store. Create it with New.
type Store struct {
	opts store.Options

	mu      sync.Mutex
	seq     uint64
	jobs    map[string]*job
	ordered []*job // creation order; the queue's job order
	tasks   map[string]*task
	// requests maps a CreateJob request id to the job it created.
	requests map[string]*job
}

var _ store.Store = (*Store)(nil)

type job struct {
	seq   uint64
	pb    *pb.Job // without phases: computed on read
	tasks []*task
	// failures counts each worker's failed attempts at the job's tasks (the blocklist).
	failures map[string]int
	// blockKind is the kind of the failure that made the latest block.
	blockKind pb.FailureKind
}

type task struct {
	job      *job
	pb       *pb.Task
	epoch    uint64
	expire   time.Time
	failures int
	expiries int
	// progress is the largest HeldLease.progress of the current lease, reported (or the
	// lease granted) at progressAt.
	progress   uint64
	progressAt time.Time
}

// New returns an empty store.
func New(opts store.Options) *Store {
	return &Store{
		opts:     opts.WithDefaults(),
		jobs:     make(map[string]*job),
		tasks:    make(map[string]*task),
		requests: make(map[string]*job),
	}
}

func (s *Store) now() time.Time { return s.opts.Clock.Now() }

// CreateJob implements store.Store.
func (s *Store) CreateJob(ctx context.Context, nj store.NewJob) (*pb.Job, error) {
	if err := nj.Check(); err != nil {
		return nil, err
	}
	s.mu.Lock()
	defer s.mu.Unlock()
	if j := s.requests[nj.RequestID]; nj.RequestID != "" && j != nil {
		return j.snapshot(), nil // a retried submission
	}
	now := timestamppb.New(s.now())
	s.seq++
	id := store.NewJobID()
	for s.jobs[id] != nil {
		id = store.NewJobID()
	}
	j := &job{seq: s.seq, failures: make(map[string]int), pb: &pb.Job{
		Id:          id,
		DisplayName: nj.DisplayName,
		State:       pb.JobState_JOB_STATE_QUEUED,
		CreateTime:  now,
		UpdateTime:  now,
		SceneDigest: nj.SceneDigest,
		Width:       nj.Width,
		Height:      nj.Height,
		Priority:    nj.Priority,
	}}
	if nj.Plan != nil {
		j.pb.Plan = proto.Clone(nj.Plan).(*pb.Plan)
	}
	s.appendTasks(j, nj.Tasks)
	s.jobs[id] = j
	s.ordered = append(s.ordered, j)
	if nj.RequestID != "" {
		s.requests[nj.RequestID] = j
	}
	return j.snapshot(), nil
}

// appendTasks adds tasks (in plan order) after j's last task, numbered on from it, with
// their first stage queued and the rest waiting.
func (s *Store) appendTasks(j *job, tasks []*pb.Task) {
	base := uint32(len(j.tasks))
	first := store.Stage(tasks[0])
	for i, t := range tasks {
		pt := proto.Clone(t).(*pb.Task)
		pt.Index = base + uint32(i)
		pt.Id = store.TaskID(j.pb.Id, pt.Index)
		pt.JobId = j.pb.Id
		pt.State = pb.TaskState_TASK_STATE_WAITING
		if store.Stage(pt) == first {
			pt.State = pb.TaskState_TASK_STATE_QUEUED
		}
		tk := &task{job: j, pb: pt}
		j.tasks = append(j.tasks, tk)
		s.tasks[pt.Id] = tk
	}
}

// snapshot returns a copy of the job with the phase progress of its latest round.
func (j *job) snapshot() *pb.Job {
	out := proto.Clone(j.pb).(*pb.Job)
	round := j.tasks[len(j.tasks)-1].pb.GetRound()
	for _, t := range j.tasks {
		if t.pb.GetRound() != round {
			continue
		}
		n := len(out.Phases)
		if n == 0 || out.Phases[n-1].Phase != t.pb.Phase {
			out.Phases = append(out.Phases, &pb.PhaseProgress{Phase: t.pb.Phase})
			n++
		}
		out.Phases[n-1].TasksTotal++
		if t.pb.State == pb.TaskState_TASK_STATE_SUCCEEDED {
			out.Phases[n-1].TasksSucceeded++
		}
	}
	return out
}

func (t *task) snapshot() *pb.Task { return proto.Clone(t.pb).(*pb.Task) }

func (s *Store) change(t *task, stateChanged, queued bool) store.Change {
	return store.Change{Job: t.job.snapshot(), Task: t.snapshot(), JobStateChanged: stateChanged, Queued: queued}
}

// GetTask implements store.Store.
func (s *Store) GetTask(ctx context.Context, taskID string) (*pb.Task, error) {
	s.mu.Lock()
	defer s.mu.Unlock()
	t := s.tasks[taskID]
	if t == nil {
		return nil, &errs.Error{Kind: errs.NotFound, Field: "task_id", Message: fmt.Sprintf("no task %q", taskID)}
	}
	return t.snapshot(), nil
}

// GetJob implements store.Store.
func (s *Store) GetJob(ctx context.Context, jobID string) (*pb.Job, error) {
	s.mu.Lock()
	defer s.mu.Unlock()
	j, err := s.job(jobID)
	if err != nil {
		return nil, err
	}
	return j.snapshot(), nil
}

func (s *Store) job(id string) (*job, error) {
	j := s.jobs[id]
	if j == nil {
		return nil, &errs.Error{Kind: errs.NotFound, Field: "job_id", Message: fmt.Sprintf("no job %q", id)}
	}
	return j, nil
}

// ListJobs implements store.Store.
func (s *Store) ListJobs(ctx context.Context, pageSize int, pageToken string) ([]*pb.Job, string, error) {
	before, given, err := store.Page('j', pageSize, pageToken)
	if err != nil {
		return nil, "", err
	}
	if !given {
		before = 1<<63 - 1
	}
	s.mu.Lock()
	defer s.mu.Unlock()
	var out []*pb.Job
	var last uint64
	for i := len(s.ordered) - 1; i >= 0; i-- {
		j := s.ordered[i]
		if j.seq >= before {
			continue
		}
		if len(out) == pageSize {
			return out, store.EncodePageToken('j', last), nil
		}
		out = append(out, j.snapshot())
		last = j.seq
	}
	return out, "", nil
}

// ListTasks implements store.Store.
func (s *Store) ListTasks(ctx context.Context, jobID string, pageSize int, pageToken string) ([]*pb.Task, string, error) {
	from, _, err := store.Page('t', pageSize, pageToken)
	if err != nil {
		return nil, "", err
	}
	s.mu.Lock()
	defer s.mu.Unlock()
	j, err := s.job(jobID)
	if err != nil {
		return nil, "", err
	}
	var out []*pb.Task
	for i := from; i < uint64(len(j.tasks)); i++ {
		if len(out) == pageSize {
			return out, store.EncodePageToken('t', i), nil
		}
		out = append(out, j.tasks[i].snapshot())
	}
	return out, "", nil
}
