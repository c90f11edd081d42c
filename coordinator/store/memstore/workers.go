package memstore

import (
	"cmp"
	"context"
	"slices"
	"sync"
	"time"

	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// Workers is the in-process store.Workers: one coordinator's registry, lost when it
// exits. Create it with NewWorkers.
type Workers struct {
	mu sync.Mutex
	m  map[string]*store.Worker
	// holder is the worker holding each task's latest lease, by task id.
	holder map[string]string
	seq    uint64 // registrations so far
}

var _ store.Workers = (*Workers)(nil)

// NewWorkers returns an empty registry.
func NewWorkers() *Workers {
	return &Workers{m: make(map[string]*store.Worker), holder: make(map[string]string)}
}

// Add implements store.Workers.
func (r *Workers) Add(_ context.Context, w store.Worker, lost time.Duration) error {
	r.mu.Lock()
	defer r.mu.Unlock()
	if len(r.m) >= store.MaxWorkers {
		var oldest *store.Worker
		for _, o := range r.m {
			if w.Registered.Sub(o.LastSeen) > lost && (oldest == nil || o.LastSeen.Before(oldest.LastSeen)) {
				oldest = o
			}
		}
		if oldest == nil {
			return store.RegistryFull()
		}
		r.forget(oldest)
	}
	r.seq++
	w.Seq = r.seq
	r.m[w.ID] = &w
	return nil
}

// forget drops w; needs r.mu held.
func (r *Workers) forget(w *store.Worker) {
	delete(r.m, w.ID)
	if w.Current != "" && r.holder[w.Current] == w.ID {
		delete(r.holder, w.Current)
	}
}

// ForgetSilent implements store.Workers.
func (r *Workers) ForgetSilent(_ context.Context, now time.Time, after time.Duration) (int, error) {
	r.mu.Lock()
	defer r.mu.Unlock()
	n := 0
	for _, w := range r.m {
		if now.Sub(w.LastSeen) > after {
			r.forget(w)
			n++
		}
	}
	return n, nil
}

// Touch implements store.Workers.
func (r *Workers) Touch(_ context.Context, id string, now time.Time) error {
	r.mu.Lock()
	defer r.mu.Unlock()
	w := r.m[id]
	if w == nil {
		return store.UnknownWorker(id, true)
	}
	w.LastSeen = now
	return nil
}

// Leased implements store.Workers.
func (r *Workers) Leased(_ context.Context, id, taskID string) error {
	r.mu.Lock()
	defer r.mu.Unlock()
	if w := r.m[id]; w != nil {
		w.Current = taskID
		r.holder[taskID] = id
	}
	return nil
}

// Ended implements store.Workers.
func (r *Workers) Ended(_ context.Context, id, taskID string, ok bool) error {
	r.mu.Lock()
	defer r.mu.Unlock()
	if w := r.m[id]; w != nil {
		r.count(w, taskID, ok)
	}
	return nil
}

// count counts w's attempt at taskID, which it no longer holds; needs r.mu held.
func (r *Workers) count(w *store.Worker, taskID string, ok bool) {
	if ok {
		w.Done++
	} else {
		w.Failed++
	}
	r.release(w, taskID)
}

// release records that w no longer holds taskID; needs r.mu held.
func (r *Workers) release(w *store.Worker, taskID string) {
	if w.Current == taskID {
		w.Current = ""
	}
	if r.holder[taskID] == w.ID {
		delete(r.holder, taskID)
	}
}

// Dropped implements store.Workers.
func (r *Workers) Dropped(_ context.Context, id, taskID string) error {
	r.mu.Lock()
	defer r.mu.Unlock()
	if w := r.m[id]; w != nil {
		r.release(w, taskID)
	}
	return nil
}

// Expired implements store.Workers.
func (r *Workers) Expired(_ context.Context, taskID string) error {
	r.mu.Lock()
	defer r.mu.Unlock()
	if w := r.m[r.holder[taskID]]; w != nil {
		r.count(w, taskID, false)
	}
	return nil
}

// List implements store.Workers.
func (r *Workers) List(_ context.Context, now time.Time, lost time.Duration, n int, token string) ([]*pb.WorkerInfo, string, error) {
	after, _, err := store.Page(store.WorkerPageToken, n, token)
	if err != nil {
		return nil, "", err
	}
	r.mu.Lock()
	defer r.mu.Unlock()
	var page []store.Worker
	for _, w := range r.m {
		if w.Seq > after {
			page = append(page, *w)
		}
	}
	slices.SortFunc(page, func(a, b store.Worker) int { return cmp.Compare(a.Seq, b.Seq) })
	out, next := store.WorkersPage(page, n, now, lost)
	return out, next, nil
}

// Live implements store.Workers.
func (r *Workers) Live(_ context.Context, now time.Time, lost time.Duration) ([]string, error) {
	r.mu.Lock()
	defer r.mu.Unlock()
	var ids []string
	for id, w := range r.m {
		if now.Sub(w.LastSeen) <= lost {
			ids = append(ids, id)
		}
	}
	slices.Sort(ids)
	return ids, nil
}

// Remove implements store.Workers.
func (r *Workers) Remove(_ context.Context, id string) error {
	r.mu.Lock()
	defer r.mu.Unlock()
	w := r.m[id]
	if w == nil {
		return store.UnknownWorker(id, false)
	}
	r.forget(w)
	return nil
}
