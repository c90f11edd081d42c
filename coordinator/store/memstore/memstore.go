// Package memstore is the in-process store.Store: all state in memory behind one mutex, so
// every method is trivially atomic. It is the embedded default (one-machine farms, `farm
// render`, unit tests); state is lost when the process exits.
//
// Cost: a lease, a completion or a report costs O(log n) in the queued tasks and the jobs
// (queue.go), never a scan of a job's tasks, so that a farm with a million tasks queued
// leases as fast as an empty one. Opening a stage and ending a job early touch that
// stage's or that round's tasks; a new job's or a new round's tasks are built before the
// lock is taken, so that creating a large job holds the lock for O(1).
package memstore

import (
	"cmp"
	"context"
	"fmt"
	"slices"
	"strconv"
	"strings"
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
	ordered []*job // creation order: ListJobs
	// requests maps a CreateJob request id to the job it created.
	requests map[string]*job
	ready    map[pb.Phase]*readyQueue
	delayed  delayQueue
	leases   map[*task]struct{} // tasks leased now
}

var _ store.Store = (*Store)(nil)

type job struct {
	seq uint64
	pb  *pb.Job // without phases: progress holds them
	// tasks in plan order; a task's index is its position.
	tasks []*task
	// failures counts each worker's failed attempts at the job's tasks (the blocklist).
	failures map[string]int
	// blockKind is the kind of the failure that made the latest block.
	blockKind pb.FailureKind
	// request is the CreateJob request id that made it, if any.
	request string

	// The current stage is tasks[cur:end]: next is the first of them never leased since
	// the stage opened, returned the indices of those that went back to the queue, and
	// left the number not yet succeeded.
	cur, end, next, left int
	returned             indexHeap
	held                 int // leases held now
	// readyAt is the job's position in the ready queue of readyPhase, -1 if in none.
	readyAt    int
	readyPhase pb.Phase
	// progress is Job.phases: the latest round's tasks per phase.
	progress []*pb.PhaseProgress
}

func (j *job) ended() bool { return store.Ended(j.pb.State) }

type task struct {
	job      *job
	pb       *pb.Task
	epoch    uint64
	expire   time.Time
	retryAt  time.Time // while in the delay queue
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
		requests: make(map[string]*job),
		ready:    make(map[pb.Phase]*readyQueue),
		leases:   make(map[*task]struct{}),
	}
}

func (s *Store) now() time.Time { return s.opts.Clock.Now() }

// CreateJob implements store.Store. The job and its tasks are built before the lock is
// taken.
func (s *Store) CreateJob(ctx context.Context, nj store.NewJob) (*pb.Job, error) {
	if err := nj.Check(); err != nil {
		return nil, err
	}
	now := timestamppb.New(s.now())
	j := &job{failures: make(map[string]int), readyAt: -1, pb: &pb.Job{
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
	j.tasks = newTasks(j, nj.Tasks, 0)
	j.stamp(store.NewJobID())

	s.mu.Lock()
	defer s.mu.Unlock()
	if old := s.requests[nj.RequestID]; nj.RequestID != "" && old != nil {
		return old.snapshot(), nil // a retried submission
	}
	for s.jobs[j.pb.Id] != nil {
		j.stamp(store.NewJobID())
	}
	s.seq++
	j.seq = s.seq
	s.jobs[j.pb.Id] = j
	s.ordered = append(s.ordered, j)
	if nj.RequestID != "" {
		s.requests[nj.RequestID] = j
		j.request = nj.RequestID
	}
	s.openRound(j, 0)
	return j.snapshot(), nil
}

// newTasks copies a plan's tasks into tasks of j numbered from base, all waiting.
func newTasks(j *job, plan []*pb.Task, base int) []*task {
	out := make([]*task, len(plan))
	for i, t := range plan {
		pt := proto.Clone(t).(*pb.Task)
		pt.Index = uint32(base + i)
		pt.State = pb.TaskState_TASK_STATE_WAITING
		out[i] = &task{job: j, pb: pt}
	}
	return out
}

// stamp gives j the id id and its tasks theirs.
func (j *job) stamp(id string) {
	j.pb.Id = id
	for _, t := range j.tasks {
		t.pb.JobId = id
		t.pb.Id = store.TaskID(id, t.pb.Index)
	}
}

// openRound starts the round whose first task is tasks[first]: its progress is the job's
// phases from now on, and its first stage is queued.
func (s *Store) openRound(j *job, first int) {
	j.progress = nil
	round := j.tasks[first].pb.GetRound()
	for _, t := range j.tasks[first:] {
		if t.pb.GetRound() != round {
			break
		}
		n := len(j.progress)
		if n == 0 || j.progress[n-1].Phase != t.pb.Phase {
			j.progress = append(j.progress, &pb.PhaseProgress{Phase: t.pb.Phase})
			n++
		}
		j.progress[n-1].TasksTotal++
	}
	s.openStage(j, first)
}

// openStage queues the stage whose first task is tasks[first].
func (s *Store) openStage(j *job, first int) {
	stage := store.Stage(j.tasks[first].pb)
	end := first
	for end < len(j.tasks) && store.Stage(j.tasks[end].pb) == stage {
		j.tasks[end].pb.State = pb.TaskState_TASK_STATE_QUEUED
		end++
	}
	j.cur, j.end, j.next, j.left = first, end, first, end-first
	j.returned = j.returned[:0]
	s.place(j)
}

// countSucceeded counts t's success in the progress of the latest round.
func (j *job) countSucceeded(t *task) {
	if t.pb.GetRound() != j.tasks[len(j.tasks)-1].pb.GetRound() {
		return
	}
	for _, p := range j.progress {
		if p.Phase == t.pb.Phase {
			p.TasksSucceeded++
			return
		}
	}
}

// snapshot returns a copy of the job with the phase progress of its latest round. The
// round reports are shared, not copied (they never change once recorded), so that the
// cost of a snapshot does not grow with the rounds.
func (j *job) snapshot() *pb.Job {
	rounds := j.pb.Rounds
	j.pb.Rounds = nil
	out := proto.Clone(j.pb).(*pb.Job)
	j.pb.Rounds = rounds
	out.Rounds = slices.Clone(rounds)
	for _, p := range j.progress {
		out.Phases = append(out.Phases, proto.Clone(p).(*pb.PhaseProgress))
	}
	return out
}

func (t *task) snapshot() *pb.Task { return proto.Clone(t.pb).(*pb.Task) }

func (s *Store) change(t *task, stateChanged, queued bool) store.Change {
	return store.Change{Job: t.job.snapshot(), Task: t.snapshot(), JobStateChanged: stateChanged, Queued: queued}
}

// task returns the task taskID names ("{job}.{index}"), or nil.
func (s *Store) task(taskID string) *task {
	k := strings.LastIndexByte(taskID, '.')
	if k < 0 {
		return nil
	}
	j := s.jobs[taskID[:k]]
	i, err := strconv.Atoi(taskID[k+1:])
	if j == nil || err != nil || i < 0 || i >= len(j.tasks) || j.tasks[i].pb.Id != taskID {
		return nil
	}
	return j.tasks[i]
}

func noTask(taskID string) error {
	return &errs.Error{Kind: errs.NotFound, Field: "task_id", Message: fmt.Sprintf("no task %q", taskID)}
}

// GetTask implements store.Store.
func (s *Store) GetTask(ctx context.Context, taskID string) (*pb.Task, error) {
	s.mu.Lock()
	defer s.mu.Unlock()
	t := s.task(taskID)
	if t == nil {
		return nil, noTask(taskID)
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
	// ordered is sorted by seq: start below the first job not older than the token.
	i, _ := slices.BinarySearchFunc(s.ordered, before, func(j *job, seq uint64) int { return cmp.Compare(j.seq, seq) })
	var out []*pb.Job
	for i--; i >= 0; i-- {
		if len(out) == pageSize {
			return out, store.EncodePageToken('j', s.ordered[i+1].seq), nil
		}
		out = append(out, s.ordered[i].snapshot())
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
