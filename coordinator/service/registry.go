package service

import (
	"cmp"
	"crypto/rand"
	"crypto/sha256"
	"crypto/subtle"
	"encoding/hex"
	"fmt"
	"slices"
	"sync"
	"time"

	"google.golang.org/protobuf/types/known/timestamppb"

	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// Limits of the worker registry (docs/limits.md).
const (
	// MaxWorkers bounds the workers registered with one coordinator. At the limit a
	// registration forgets the longest-silent LOST worker to make room, and fails with
	// RESOURCE_EXHAUSTED if none is lost.
	MaxWorkers = 10000
	// ForgetAfterLeases: a worker not heard from for this many lease durations is
	// forgotten (its leases expired long before); if it comes back, its next heartbeat
	// or lease gets NOT_FOUND and it registers again.
	ForgetAfterLeases = 4
)

// Page sizes of ListWorkers (job.proto).
const (
	DefaultWorkersPage = 100
	MaxWorkersPage     = 1000
)

// workerPageToken names a ListWorkers listing's page tokens (store.EncodePageToken):
// "w<seq>", the workers registered after the seq-th registration.
const workerPageToken = 'w'

// registry is the in-memory list of registered workers and what each is doing, for
// ListWorkers. Leases themselves live in the store; the registry only mirrors what this
// coordinator saw (grants, reports, revocations, expiries), so another replica's view of
// a worker may differ.
type registry struct {
	mu sync.Mutex
	m  map[string]*worker
	// holder is the worker holding each task's latest lease granted here, by task id.
	holder map[string]string
	seq    uint64 // registrations so far
}

func newRegistry() registry {
	return registry{m: make(map[string]*worker), holder: make(map[string]string)}
}

type worker struct {
	id       string
	seq      uint64 // the registration's place in the listing
	hostname string
	cores    uint32
	version  string
	// registered is when it registered; lastSeen when it last heartbeat or polled.
	registered, lastSeen time.Time
	// current is the task it holds a lease on ("" if none): the latest lease granted.
	current string
	// done and failed count the tasks it completed and failed (lost leases included).
	done, failed uint64
}

// newWorkerSecret returns a fresh registration secret and the worker id it makes.
func newWorkerSecret() (secret, id string) {
	var b [32]byte
	_, _ = rand.Read(b[:])
	secret = hex.EncodeToString(b[:])
	return secret, workerIDOf(secret)
}

// workerIDOf is the id a registration secret makes: 96 bits of its SHA-256, so that an id
// cannot be turned back into its secret, and any coordinator can check a pair without
// having seen the registration.
func workerIDOf(secret string) string {
	sum := sha256.Sum256([]byte("photonfarm worker id\x00" + secret))
	return "w-" + hex.EncodeToString(sum[:12])
}

// secretFits reports whether secret is the one id was made from, in constant time.
func secretFits(id, secret string) bool {
	return subtle.ConstantTimeCompare([]byte(workerIDOf(secret)), []byte(id)) == 1
}

// add registers w under the id its secret makes, making room by forgetting the
// longest-silent lost worker when MaxWorkers are registered.
func (r *registry) add(w *worker, now time.Time, lost time.Duration) error {
	r.mu.Lock()
	defer r.mu.Unlock()
	if len(r.m) >= MaxWorkers {
		var oldest *worker
		for _, o := range r.m {
			if now.Sub(o.lastSeen) > lost && (oldest == nil || o.lastSeen.Before(oldest.lastSeen)) {
				oldest = o
			}
		}
		if oldest == nil {
			return errs.E(errs.ResourceExhausted, "%d workers are registered, the most a coordinator keeps, and none is lost: "+
				"try again once workers unregister or stop heartbeating", MaxWorkers)
		}
		r.forget(oldest)
	}
	r.seq++
	w.seq = r.seq
	r.m[w.id] = w
	return nil
}

// forget drops w; needs r.mu held.
func (r *registry) forget(w *worker) {
	delete(r.m, w.id)
	if w.current != "" && r.holder[w.current] == w.id {
		delete(r.holder, w.current)
	}
}

// forgetSilent forgets the workers not heard from for longer than after and returns
// how many.
func (r *registry) forgetSilent(now time.Time, after time.Duration) int {
	r.mu.Lock()
	defer r.mu.Unlock()
	n := 0
	for _, w := range r.m {
		if now.Sub(w.lastSeen) > after {
			r.forget(w)
			n++
		}
	}
	return n
}

// touch records that id was heard from; it fails for an unknown worker.
func (r *registry) touch(id string, now time.Time) error {
	r.mu.Lock()
	defer r.mu.Unlock()
	w := r.m[id]
	if w == nil {
		return &errs.Error{Kind: errs.NotFound, Field: "worker_id", Message: fmt.Sprintf("unknown worker %q; register again", id)}
	}
	w.lastSeen = now
	return nil
}

// leased records that id was granted a lease on taskID. Unknown ids (the coordinator's
// builder) are ignored, as in the methods below.
func (r *registry) leased(id, taskID string) {
	r.mu.Lock()
	defer r.mu.Unlock()
	if w := r.m[id]; w != nil {
		w.current = taskID
		r.holder[taskID] = id
	}
}

// ended records that id's attempt at taskID ended, successfully (ok) or not.
func (r *registry) ended(id, taskID string, ok bool) {
	r.mu.Lock()
	defer r.mu.Unlock()
	w := r.m[id]
	if w == nil {
		return
	}
	if ok {
		w.done++
	} else {
		w.failed++
	}
	r.release(w, taskID)
}

// release records that w no longer holds taskID; needs r.mu held.
func (r *registry) release(w *worker, taskID string) {
	if w.current == taskID {
		w.current = ""
	}
	if r.holder[taskID] == w.id {
		delete(r.holder, taskID)
	}
}

// dropped records that id no longer holds taskID (released, revoked), counting nothing.
func (r *registry) dropped(id, taskID string) {
	r.mu.Lock()
	defer r.mu.Unlock()
	if w := r.m[id]; w != nil {
		r.release(w, taskID)
	}
}

// expired records that the lease on taskID expired: its holder (the store no longer names
// it) failed the task.
func (r *registry) expired(taskID string) {
	r.mu.Lock()
	defer r.mu.Unlock()
	if w := r.m[r.holder[taskID]]; w != nil {
		w.failed++
		r.release(w, taskID)
	}
}

// list returns a page of at most n workers by registration, oldest first, from the page
// token (empty: the first page), and the next page's token; a worker not heard from for
// longer than lost is LOST.
func (r *registry) list(now time.Time, lost time.Duration, n int, token string) ([]*pb.WorkerInfo, string, error) {
	after, _, err := store.Page(workerPageToken, n, token)
	if err != nil {
		return nil, "", err
	}
	r.mu.Lock()
	defer r.mu.Unlock()
	var page []*worker
	for _, w := range r.m {
		if w.seq > after {
			page = append(page, w)
		}
	}
	slices.SortFunc(page, func(a, b *worker) int { return cmp.Compare(a.seq, b.seq) })
	next := ""
	if len(page) > n {
		page = page[:n]
		next = store.EncodePageToken(workerPageToken, page[n-1].seq)
	}
	out := make([]*pb.WorkerInfo, len(page))
	for i, w := range page {
		state := pb.WorkerState_WORKER_STATE_IDLE
		switch {
		case now.Sub(w.lastSeen) > lost:
			state = pb.WorkerState_WORKER_STATE_LOST
		case w.current != "":
			state = pb.WorkerState_WORKER_STATE_BUSY
		}
		out[i] = &pb.WorkerInfo{
			Id:            w.id,
			Hostname:      w.hostname,
			Cores:         w.cores,
			Version:       w.version,
			State:         state,
			CurrentTaskId: w.current,
			TasksDone:     w.done,
			TasksFailed:   w.failed,
			RegisterTime:  timestamppb.New(w.registered),
			LastHeartbeat: timestamppb.New(w.lastSeen),
		}
	}
	return out, next, nil
}

// live returns the ids of the workers heard from within lost: registered and not LOST.
func (r *registry) live(now time.Time, lost time.Duration) []string {
	r.mu.Lock()
	defer r.mu.Unlock()
	var ids []string
	for id, w := range r.m {
		if now.Sub(w.lastSeen) <= lost {
			ids = append(ids, id)
		}
	}
	slices.Sort(ids)
	return ids
}

// remove forgets a worker; NotFound if it was not registered.
func (r *registry) remove(id string) error {
	r.mu.Lock()
	defer r.mu.Unlock()
	w := r.m[id]
	if w == nil {
		return &errs.Error{Kind: errs.NotFound, Field: "worker_id", Message: fmt.Sprintf("unknown worker %q", id)}
	}
	r.forget(w)
	return nil
}
