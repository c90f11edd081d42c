package dashboard

import (
	"context"
	"sync"
	"time"

	"google.golang.org/protobuf/proto"

	"photonfarm/client"
	pb "photonfarm/proto/renderfarm/v1"
)

// jobFeeds shares the job list among the /api/events streams: the streams of one token
// (a browser's tabs, or all browsers logged in with one token) share one feed, which
// polls ListJobs every JobsPoll while it has a subscriber and hands each subscriber what
// changed. Without it every stream polled the whole list twice a second and sent all of
// it whenever any job changed. Feeds are kept by token, so a stream is only ever sent
// what the coordinator answered its own token.
type jobFeeds struct {
	s     *Server
	mu    sync.Mutex
	feeds map[string]*jobFeed
}

// jobFeed is one token's poll of the job list and its subscribers.
type jobFeed struct {
	feeds *jobFeeds
	token string
	stop  context.CancelFunc
	ready chan struct{} // closed after the first poll

	mu   sync.Mutex
	jobs []*pb.Job // the latest list, newest first
	err  error     // why the feed ended
	subs map[*jobSub]struct{}
}

// jobSub is a stream's view of a feed: what changed since the stream last took it.
type jobSub struct {
	feed    *jobFeed
	mu      sync.Mutex
	changed []*pb.Job // newest first, each job once
	removed []string
	err     error // the feed ended
	wake    chan struct{}
}

func newJobFeeds(s *Server) *jobFeeds { return &jobFeeds{s: s, feeds: make(map[string]*jobFeed)} }

// subscribe joins token's feed (starting it if there is none) and returns the job list
// as it stands, the first poll's error if it failed, or ctx's.
func (fs *jobFeeds) subscribe(ctx context.Context, token string) (*jobSub, []*pb.Job, error) {
	fs.mu.Lock()
	f := fs.feeds[token]
	if f == nil {
		fctx, stop := context.WithCancel(context.Background())
		f = &jobFeed{feeds: fs, token: token, stop: stop, ready: make(chan struct{}), subs: make(map[*jobSub]struct{})}
		fs.feeds[token] = f
		go f.run(client.ContextWithToken(fctx, token))
	}
	sub := &jobSub{feed: f, wake: make(chan struct{}, 1)}
	f.mu.Lock()
	f.subs[sub] = struct{}{}
	f.mu.Unlock()
	fs.mu.Unlock()

	select {
	case <-f.ready:
	case <-ctx.Done():
		sub.leave()
		return nil, nil, ctx.Err()
	}
	f.mu.Lock()
	defer f.mu.Unlock()
	if f.err != nil {
		delete(f.subs, sub)
		return nil, nil, f.err
	}
	// Changes published between the first poll and now are in the list returned.
	sub.take()
	return sub, f.jobs, nil
}

// run polls until the feed has no subscriber (stop) or a poll fails.
func (f *jobFeed) run(ctx context.Context) {
	tick := time.NewTicker(f.feeds.s.cfg.JobsPoll)
	defer tick.Stop()
	for first := true; ; first = false {
		jobs, err := f.feeds.s.pollJobs(ctx)
		if ctx.Err() != nil {
			return
		}
		f.publish(jobs, err)
		if first {
			close(f.ready)
		}
		if err != nil {
			f.feeds.drop(f)
			return
		}
		select {
		case <-ctx.Done():
			return
		case <-tick.C:
		}
	}
}

// publish records a poll's list and gives each subscriber the jobs that differ from
// the last list, or the error.
func (f *jobFeed) publish(jobs []*pb.Job, err error) {
	f.mu.Lock()
	defer f.mu.Unlock()
	if err != nil {
		f.err = err
		for sub := range f.subs {
			sub.add(nil, nil, err)
		}
		return
	}
	before := make(map[string]*pb.Job, len(f.jobs))
	for _, j := range f.jobs {
		before[j.GetId()] = j
	}
	var changed []*pb.Job
	for _, j := range jobs {
		if old, ok := before[j.GetId()]; !ok || !proto.Equal(old, j) {
			changed = append(changed, j)
		}
		delete(before, j.GetId())
	}
	var removed []string
	for id := range before {
		removed = append(removed, id)
	}
	f.jobs = jobs
	if len(changed) == 0 && len(removed) == 0 {
		return
	}
	for sub := range f.subs {
		sub.add(changed, removed, nil)
	}
}

// drop forgets f, if it is still token's feed, so that the next stream starts another.
func (fs *jobFeeds) drop(f *jobFeed) {
	fs.mu.Lock()
	defer fs.mu.Unlock()
	if fs.feeds[f.token] == f {
		delete(fs.feeds, f.token)
	}
}

// leave unsubscribes; the feed stops with its last subscriber.
func (sub *jobSub) leave() {
	f := sub.feed
	f.feeds.mu.Lock()
	defer f.feeds.mu.Unlock()
	f.mu.Lock()
	delete(f.subs, sub)
	last := len(f.subs) == 0
	f.mu.Unlock()
	if last {
		if f.feeds.feeds[f.token] == f {
			delete(f.feeds.feeds, f.token)
		}
		f.stop()
	}
}

// add merges a change into what the subscriber has not taken yet.
func (sub *jobSub) add(changed []*pb.Job, removed []string, err error) {
	sub.mu.Lock()
	defer sub.mu.Unlock()
	if err != nil {
		sub.err = err
	}
	if len(changed) > 0 {
		// The newer state of a job replaces the one not yet sent; the newest jobs lead.
		fresh := make(map[string]bool, len(changed))
		for _, j := range changed {
			fresh[j.GetId()] = true
		}
		kept := sub.changed[:0]
		for _, j := range sub.changed {
			if !fresh[j.GetId()] {
				kept = append(kept, j)
			}
		}
		sub.changed = append(append([]*pb.Job(nil), changed...), kept...)
	}
	sub.removed = append(sub.removed, removed...)
	select {
	case sub.wake <- struct{}{}:
	default:
	}
}

// take returns and clears what changed since the last take.
func (sub *jobSub) take() (changed []*pb.Job, removed []string, err error) {
	sub.mu.Lock()
	defer sub.mu.Unlock()
	changed, removed, err = sub.changed, sub.removed, sub.err
	sub.changed, sub.removed = nil, nil
	return changed, removed, err
}
