// Package events broadcasts each job's WatchJobResponse events to the watchers of that
// job. Publishing never blocks: every watcher has a bounded queue, and when a slow watcher
// falls more than its queue behind, the queued events are coalesced into the newest one
// (every event carries the whole job after the change, so the newest event alone says
// where the job stands). The terminal event is the newest of a job, so no watcher ever
// misses it.
package events

import (
	"context"
	"sync"

	pb "photonfarm/proto/renderfarm/v1"
)

// DefaultQueueLen is how many events a watcher may fall behind before coalescing.
const DefaultQueueLen = 256

// Broker fans events out to watchers. The zero value is not usable; call NewBroker.
type Broker struct {
	queueLen int

	mu       sync.Mutex
	watchers map[string]map[*Watcher]struct{}
}

// NewBroker returns a Broker whose watchers queue up to queueLen events
// (<= 0 selects DefaultQueueLen).
func NewBroker(queueLen int) *Broker {
	if queueLen <= 0 {
		queueLen = DefaultQueueLen
	}
	return &Broker{queueLen: queueLen, watchers: make(map[string]map[*Watcher]struct{})}
}

// Watcher receives one job's events. Close it when done.
type Watcher struct {
	b     *Broker
	jobID string

	mu        sync.Mutex
	queue     []*pb.WatchJobResponse
	coalesced int
	ready     chan struct{} // has a token while queue is non-empty
}

// Watch subscribes to jobID's events published from now on.
func (b *Broker) Watch(jobID string) *Watcher {
	w := &Watcher{b: b, jobID: jobID, ready: make(chan struct{}, 1)}
	b.mu.Lock()
	defer b.mu.Unlock()
	if b.watchers[jobID] == nil {
		b.watchers[jobID] = make(map[*Watcher]struct{})
	}
	b.watchers[jobID][w] = struct{}{}
	return w
}

// Publish hands ev to every watcher of ev.Job.Id without blocking.
func (b *Broker) Publish(ev *pb.WatchJobResponse) {
	b.mu.Lock()
	defer b.mu.Unlock()
	for w := range b.watchers[ev.GetJob().GetId()] {
		w.push(ev, b.queueLen)
	}
}

// Watchers returns how many watchers jobID has (for tests and metrics).
func (b *Broker) Watchers(jobID string) int {
	b.mu.Lock()
	defer b.mu.Unlock()
	return len(b.watchers[jobID])
}

func (w *Watcher) push(ev *pb.WatchJobResponse, max int) {
	w.mu.Lock()
	if len(w.queue) >= max {
		w.coalesced += len(w.queue)
		w.queue = w.queue[:0]
	}
	w.queue = append(w.queue, ev)
	w.mu.Unlock()
	select {
	case w.ready <- struct{}{}:
	default:
	}
}

// Next returns the next event, waiting for one until ctx is done. Events are shared
// between watchers: do not modify them.
func (w *Watcher) Next(ctx context.Context) (*pb.WatchJobResponse, error) {
	for {
		w.mu.Lock()
		if len(w.queue) > 0 {
			ev := w.queue[0]
			w.queue[0] = nil
			w.queue = w.queue[1:]
			more := len(w.queue) > 0
			w.mu.Unlock()
			if more {
				select {
				case w.ready <- struct{}{}:
				default:
				}
			}
			return ev, nil
		}
		w.mu.Unlock()
		select {
		case <-w.ready:
		case <-ctx.Done():
			return nil, ctx.Err()
		}
	}
}

// Coalesced returns how many events were dropped because the watcher fell behind.
func (w *Watcher) Coalesced() int {
	w.mu.Lock()
	defer w.mu.Unlock()
	return w.coalesced
}

// Close unsubscribes the watcher.
func (w *Watcher) Close() {
	b := w.b
	b.mu.Lock()
	defer b.mu.Unlock()
	delete(b.watchers[w.jobID], w)
	if len(b.watchers[w.jobID]) == 0 {
		delete(b.watchers, w.jobID)
	}
}
