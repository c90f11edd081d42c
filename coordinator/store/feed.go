package store

import "context"

// Feed is offered by a Store that several coordinators (replicas) share: each follows the
// changes the others make, so that its watchers (WatchJob) and its waiting workers (the
// LeaseTask long poll) hear of them as of its own. memstore, which no other process
// shares, has none.
type Feed interface {
	// Follow calls fn with every change that other Store values on the same data make from
	// now on, in the order they were made, until ctx ends; it then returns ctx's error.
	// A change made by a coordinator that died right after is followed like any other:
	// it entered the feed in the same step that stored it. fn runs on Follow's goroutine,
	// so a slow fn delays the changes after it, never loses them, unless the follower
	// falls behind by more than the feed keeps (redisstore.FeedLength).
	Follow(ctx context.Context, fn func(Remote)) error
}

// Remote is a change another replica made, as the feed names it.
type Remote struct {
	JobID, TaskID string
	// JobStateChanged and Queued are the Change's.
	JobStateChanged, Queued bool
	// Blocks says that the job has blocked a worker, now or before (UnblockWorker).
	Blocks bool
	// Load reads the job and the task as they stand now (they may have changed again
	// since), for a follower that needs them; a job deleted since loads as the zero Change.
	Load func(ctx context.Context) (Change, error)
}
