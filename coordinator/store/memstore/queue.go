package memstore

import (
	"container/heap"

	pb "photonfarm/proto/renderfarm/v1"
)

// The queues that make a lease cost O(log n) in the queued tasks and the jobs:
//
//   - readyQueue (one per phase): the jobs whose current stage is of that phase and has a
//     leasable task, ordered as the store package's Scheduling says (priority, then leases
//     held, then age), so that the best job is the heap's head;
//   - job.returned: the indices of a stage's tasks that went back to the queue (released,
//     expired, out of their backoff), lowest first; the tasks of the stage never leased
//     are the range [job.next, job.end), so opening a stage queues no task one by one;
//   - delayQueue: the tasks in backoff, earliest retry time first, moved to their job's
//     returned when it has passed.

// before reports whether job a is leased before job b.
func before(a, b *job) bool {
	if a.pb.Priority != b.pb.Priority {
		return a.pb.Priority > b.pb.Priority
	}
	if a.held != b.held {
		return a.held < b.held
	}
	return a.seq < b.seq
}

// readyQueue is a heap of jobs (container/heap); each job records its position.
type readyQueue []*job

func (q readyQueue) Len() int           { return len(q) }
func (q readyQueue) Less(i, k int) bool { return before(q[i], q[k]) }
func (q readyQueue) Swap(i, k int) {
	q[i], q[k] = q[k], q[i]
	q[i].readyAt, q[k].readyAt = i, k
}
func (q *readyQueue) Push(x any) {
	j := x.(*job)
	j.readyAt = len(*q)
	*q = append(*q, j)
}
func (q *readyQueue) Pop() any {
	old := *q
	j := old[len(old)-1]
	old[len(old)-1] = nil
	*q = old[:len(old)-1]
	j.readyAt = -1
	return j
}

// place puts j in the ready queue of its current stage's phase, at its rank, if it has a
// leasable task, and takes it out of any ready queue otherwise. Every change to a job's
// priority, held leases or queue calls it.
func (s *Store) place(j *job) {
	leasable := !j.ended() && (j.next < j.end || len(j.returned) > 0)
	var phase pb.Phase
	if leasable {
		phase = j.tasks[j.cur].pb.Phase
	}
	if j.readyAt >= 0 && (!leasable || j.readyPhase != phase) {
		heap.Remove(s.ready[j.readyPhase], j.readyAt)
	}
	if !leasable {
		return
	}
	q := s.ready[phase]
	if q == nil {
		q = &readyQueue{}
		s.ready[phase] = q
	}
	if j.readyAt < 0 {
		j.readyPhase = phase
		heap.Push(q, j)
		return
	}
	heap.Fix(q, j.readyAt)
}

// head returns the best job of phase's ready queue that has not blocked workerID, or nil.
// Blocked jobs at the head are set aside and put back: a worker is blocked from few jobs.
func (s *Store) head(phase pb.Phase, workerID string) *job {
	q := s.ready[phase]
	if q == nil {
		return nil
	}
	var aside []*job
	defer func() {
		for _, j := range aside {
			heap.Push(q, j)
		}
	}()
	for q.Len() > 0 {
		j := (*q)[0]
		if !blocked(j, workerID) {
			return j
		}
		aside = append(aside, heap.Pop(q).(*job))
	}
	return nil
}

// indexHeap is a min-heap of task indices.
type indexHeap []int

func (h indexHeap) Len() int           { return len(h) }
func (h indexHeap) Less(i, k int) bool { return h[i] < h[k] }
func (h indexHeap) Swap(i, k int)      { h[i], h[k] = h[k], h[i] }
func (h *indexHeap) Push(x any)        { *h = append(*h, x.(int)) }
func (h *indexHeap) Pop() any {
	old := *h
	i := old[len(old)-1]
	*h = old[:len(old)-1]
	return i
}

// delayQueue is a heap of tasks in backoff by retry time.
type delayQueue []*task

func (q delayQueue) Len() int           { return len(q) }
func (q delayQueue) Less(i, k int) bool { return q[i].retryAt.Before(q[k].retryAt) }
func (q delayQueue) Swap(i, k int)      { q[i], q[k] = q[k], q[i] }
func (q *delayQueue) Push(x any)        { *q = append(*q, x.(*task)) }
func (q *delayQueue) Pop() any {
	old := *q
	t := old[len(old)-1]
	old[len(old)-1] = nil
	*q = old[:len(old)-1]
	return t
}
