package redisstore

import (
	"context"
	"errors"
	"strings"
	"time"

	"github.com/redis/go-redis/v9"

	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
)

// FeedLength is about how many changes the feed keeps (XADD MAXLEN ~): a follower that
// falls further behind misses the oldest. At 5,000 changes a second, ten seconds of them,
// some 7 MB of Redis memory.
const FeedLength = 50000

var _ store.Feed = (*Store)(nil)

// feedBatch is how many changes one XREAD returns, and feedBlock how long it waits for
// one; a follower whose Redis fails waits feedRetry before it reads again.
const (
	feedBatch = 1000
	feedBlock = time.Second
	feedRetry = 500 * time.Millisecond
)

// Follow implements store.Feed: it reads the changes stream that every script's ok()
// appends to (scripts.go), from its end as it stands now, and skips the changes this Store
// value made, whose operation keys begin with its own origin.
func (s *Store) Follow(ctx context.Context, fn func(store.Remote)) error {
	key := s.key(changesKey)
	wait := func() {
		select {
		case <-time.After(feedRetry):
		case <-ctx.Done():
		}
	}
	last, err := s.feedEnd(ctx, key)
	for ; err != nil; last, err = s.feedEnd(ctx, key) {
		if ctx.Err() != nil {
			return ctx.Err()
		}
		wait()
	}
	for {
		streams, err := s.rdb.XRead(ctx, &redis.XReadArgs{Streams: []string{key, last}, Count: feedBatch, Block: feedBlock}).Result()
		switch {
		case ctx.Err() != nil:
			return ctx.Err()
		case errors.Is(err, redis.Nil): // nothing new within feedBlock
			continue
		case err != nil: // Redis down or restarting: read on from the same entry
			wait()
			continue
		}
		for _, st := range streams {
			for _, m := range st.Messages {
				last = m.ID
				if r, ok := s.remote(m.Values); ok {
					fn(r)
				}
			}
		}
	}
}

// feedEnd is the id of the newest change in the feed ("0-0" if there is none).
func (s *Store) feedEnd(ctx context.Context, key string) (string, error) {
	l, err := s.rdb.XRevRangeN(ctx, key, "+", "-", 1).Result()
	if err != nil {
		return "", err
	}
	if len(l) == 0 {
		return "0-0", nil
	}
	return l[0].ID, nil
}

// remote reads one feed entry, the skeleton ok() wrote; false for this Store's own.
func (s *Store) remote(v map[string]any) (store.Remote, bool) {
	str := func(k string) string { x, _ := v[k].(string); return x }
	if strings.HasPrefix(str("o"), s.ops) {
		return store.Remote{}, false
	}
	jid, tid, changed, queued := str("j"), str("t"), str("c"), str("q")
	return store.Remote{
		JobID:           jid,
		TaskID:          tid,
		JobStateChanged: changed == "1",
		Queued:          queued == "1",
		Blocks:          str("b") == "1",
		Load: func(ctx context.Context) (store.Change, error) {
			v, err := loadScript.Run(ctx, s.rdb, []string{s.key(jobsKey)}, s.prefix, micros(s.opts.Clock.Now()), changed, queued, jid, tid).Result()
			if err != nil {
				return store.Change{}, redisErr(err)
			}
			r, err := s.decodeReply(ctx, v)
			if err != nil {
				return store.Change{}, errs.Wrap(errs.Internal, err, "loading a change of job "+jid)
			}
			return r.change, nil
		},
	}, true
}

// loadScript: ARGV[3] job state changed, [4] queued, [5] job id, [6] task id or empty. It
// answers a feed entry as the script that made the change answered it, with the records
// as they stand now, or NONE for a job no longer there. It changes nothing.
var loadScript = func() *redis.Script {
	sc := redis.NewScript(preamble + lib + `
if unknown(ARGV[5]) then return {'NONE'} end
return render({'OK', tonumber(ARGV[3]), tonumber(ARGV[4]), ARGV[5], ARGV[6]})
`)
	scripts = append(scripts, sc)
	return sc
}()
