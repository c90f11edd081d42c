package service

import (
	"context"
	"sync"

	"photonfarm/contract/pages"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// Jobs that no worker can run: a job every live worker is blocked from fails, with the
// reason, rather than waiting for ever. It is checked when a block happens
// (failIfEveryWorkerBlocked) and again periodically (FailBlockedJobs), because a job may
// lose its last unblocked worker later: the worker is lost, or unregisters.

// blockedJobs is the set of jobs that have blocked a worker and not ended, as this
// coordinator last saw them (publish keeps it).
type blockedJobs struct {
	mu     sync.Mutex
	seeded bool
	ids    map[string]bool
}

// track adds or drops j as it now stands.
func (b *blockedJobs) track(j *pb.Job) {
	b.mu.Lock()
	defer b.mu.Unlock()
	if len(j.GetBlockedWorkers()) > 0 && !store.Ended(j.GetState()) {
		b.ids[j.GetId()] = true
	} else {
		delete(b.ids, j.GetId())
	}
}

func (b *blockedJobs) list() []string {
	b.mu.Lock()
	defer b.mu.Unlock()
	ids := make([]string, 0, len(b.ids))
	for id := range b.ids {
		ids = append(ids, id)
	}
	return ids
}

// FailBlockedJobs fails every job that has blocked workers and that every live worker
// (registered, heard from within a lease duration) is blocked from. The coordinator calls
// it periodically; the first call learns the blocked jobs from the store (they may predate
// this process), later ones check those this coordinator has seen block a worker since.
func (s *Service) FailBlockedJobs(ctx context.Context) error {
	if err := s.seedBlocked(ctx); err != nil {
		return err
	}
	ids := s.blocked.list()
	if len(ids) == 0 {
		return nil
	}
	live, err := s.workers.Live(ctx, s.cfg.Clock.Now(), s.cfg.LeaseDuration)
	if err != nil {
		return err
	}
	for _, id := range ids {
		if err := s.failBlockedJob(ctx, id, live); err != nil {
			return err
		}
	}
	return nil
}

// seedBlocked tracks the blocked jobs the store holds, once.
func (s *Service) seedBlocked(ctx context.Context) error {
	s.blocked.mu.Lock()
	seeded := s.blocked.seeded
	s.blocked.mu.Unlock()
	if seeded {
		return nil
	}
	err := pages.Each(func(token string) ([]*pb.Job, string, error) {
		return s.cfg.Store.ListJobs(ctx, MaxJobsPage, token)
	}, func(j *pb.Job) (bool, error) {
		s.blocked.track(j)
		return true, nil
	})
	if err == nil {
		s.blocked.mu.Lock()
		s.blocked.seeded = true
		s.blocked.mu.Unlock()
	}
	return err
}

// failBlockedJob fails jobID if every one of the live workers is blocked from it.
func (s *Service) failBlockedJob(ctx context.Context, jobID string, live []string) error {
	failed, err := s.cfg.Store.FailBlockedJob(ctx, jobID, live)
	if err != nil {
		return err
	}
	if failed.Job != nil {
		s.log.Warn("job failed: every worker is blocked", "job", jobID, "workers", len(live), "error", failed.Job.GetError())
		s.publish(failed)
	}
	return nil
}
