package store

import (
	"context"
	"fmt"
	"time"

	"google.golang.org/protobuf/types/known/timestamppb"

	"photonfarm/coordinator/errs"
	pb "photonfarm/proto/renderfarm/v1"
)

// MaxWorkers bounds the workers a registry keeps (docs/limits.md). At the limit a
// registration forgets the longest-silent LOST worker to make room, and fails with
// RESOURCE_EXHAUSTED if none is lost.
const MaxWorkers = 10000

// WorkerPageToken names a ListWorkers listing's page tokens (EncodePageToken): "w<seq>",
// the workers registered after the seq-th registration.
const WorkerPageToken = 'w'

// Workers is the registry of workers and what each is doing, for ListWorkers and for
// knowing which workers are live (a job every live worker is blocked from fails). Leases
// live in the Store; the registry mirrors what the coordinators saw of them (grants,
// reports, revocations, expiries). memstore keeps one per process; redisstore keeps it in
// Redis, so that every coordinator replica on one Redis lists the same workers and knows
// a worker that registered with another. The behavioural suite is storetest.RunWorkers.
//
// Times are the caller's (its clock), so that tests can drive them; lost is how long a
// worker may stay silent before it is LOST. Leased, Ended, Dropped and Expired ignore an
// unknown worker (the coordinator's own builder leases too, without registering).
type Workers interface {
	// Add registers w (Registered and LastSeen are its registration time; Seq is
	// assigned), making room at MaxWorkers by forgetting the longest-silent worker
	// silent for longer than lost.
	Add(ctx context.Context, w Worker, lost time.Duration) error
	// Touch records that id was heard from at now; NotFound for an unknown worker.
	Touch(ctx context.Context, id string, now time.Time) error
	// Leased records that id was granted a lease on taskID.
	Leased(ctx context.Context, id, taskID string) error
	// Ended records that id's attempt at taskID ended, successfully (ok) or not.
	Ended(ctx context.Context, id, taskID string, ok bool) error
	// Dropped records that id no longer holds taskID (released, revoked), counting nothing.
	Dropped(ctx context.Context, id, taskID string) error
	// Expired records that the lease on taskID expired: its latest holder failed it.
	Expired(ctx context.Context, taskID string) error
	// List returns a page of at most n workers in registration order from the page token
	// (empty: the first page), and the next page's token.
	List(ctx context.Context, now time.Time, lost time.Duration, n int, token string) ([]*pb.WorkerInfo, string, error)
	// Live returns the ids of the workers heard from within lost, sorted.
	Live(ctx context.Context, now time.Time, lost time.Duration) ([]string, error)
	// Remove forgets a worker; NotFound if it is not registered.
	Remove(ctx context.Context, id string) error
	// ForgetSilent forgets the workers not heard from for longer than after, and says how
	// many.
	ForgetSilent(ctx context.Context, now time.Time, after time.Duration) (int, error)
}

// Worker is one registration as a registry keeps it.
type Worker struct {
	ID, Hostname, Version string
	Cores                 uint32
	// Seq is the registration's place in the listing.
	Seq uint64
	// Registered is when it registered; LastSeen when it last heartbeat or polled.
	Registered, LastSeen time.Time
	// Current is the task of the latest lease granted to it, "" if it holds none.
	Current string
	// Done and Failed count the tasks it completed and failed (lost leases included).
	Done, Failed uint64
}

// Info is w as ListWorkers shows it at now: LOST if silent for longer than lost, else
// BUSY while it holds a lease, else IDLE.
func (w Worker) Info(now time.Time, lost time.Duration) *pb.WorkerInfo {
	state := pb.WorkerState_WORKER_STATE_IDLE
	switch {
	case now.Sub(w.LastSeen) > lost:
		state = pb.WorkerState_WORKER_STATE_LOST
	case w.Current != "":
		state = pb.WorkerState_WORKER_STATE_BUSY
	}
	return &pb.WorkerInfo{
		Id:            w.ID,
		Hostname:      w.Hostname,
		Cores:         w.Cores,
		Version:       w.Version,
		State:         state,
		CurrentTaskId: w.Current,
		TasksDone:     w.Done,
		TasksFailed:   w.Failed,
		RegisterTime:  timestamppb.New(w.Registered),
		LastHeartbeat: timestamppb.New(w.LastSeen),
	}
}

// WorkersPage shows ws, the workers after a page token in registration order and at least
// n+1 of them if there are more, as a page of n and the next page's token.
func WorkersPage(ws []Worker, n int, now time.Time, lost time.Duration) ([]*pb.WorkerInfo, string) {
	next := ""
	if len(ws) > n {
		ws = ws[:n]
		next = EncodePageToken(WorkerPageToken, ws[n-1].Seq)
	}
	out := make([]*pb.WorkerInfo, len(ws))
	for i, w := range ws {
		out[i] = w.Info(now, lost)
	}
	return out, next
}

// UnknownWorker is the NotFound of a call about a worker the registry does not hold;
// again says that the worker should register again.
func UnknownWorker(id string, again bool) error {
	msg := fmt.Sprintf("unknown worker %q", id)
	if again {
		msg += "; register again"
	}
	return &errs.Error{Kind: errs.NotFound, Field: "worker_id", Message: msg}
}

// RegistryFull is the refusal of a registration at MaxWorkers with none lost.
func RegistryFull() error {
	return errs.E(errs.ResourceExhausted, "%d workers are registered, the most a coordinator keeps, and none is lost: "+
		"try again once workers unregister or stop heartbeating", MaxWorkers)
}
