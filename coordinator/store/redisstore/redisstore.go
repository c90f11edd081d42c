// Package redisstore is a store.Store kept in Redis, so that the farm's state outlives a
// coordinator and several coordinators (replicas) can share it.
//
// Atomicity: every method that changes state is one Lua script (scripts.go), run with
// EVALSHA. Redis runs a script alone, start to finish, so two Store values on one Redis
// (two coordinator processes) can never interleave inside a step: a task is popped from
// its queue and leased in the same script, and every report is checked against the
// task's epoch, worker and expiry in the script that applies it. Scripts were chosen over
// WATCH/MULTI because a lease must search the queues and then write, and many lessees
// compete for the same queue: optimistic transactions would retry under exactly the load
// that matters. Reads are single commands, pipelined: a job's record is one hash (its
// round reports are only ever appended), so each record is read in one state.
//
// Epochs (fencing tokens) are task fields in Redis, grown by HINCRBY on every lease and
// never reset. Time comes from Options.Clock of the calling coordinator, passed to each
// script, so replicas should run synchronized clocks.
//
// Scheduling (priority, then fewest leases held, then age) is kept in the ready sorted
// sets by the scripts themselves, so a lease reads the best job off a set's head instead
// of scanning jobs; the reasoning is at the top of scripts.go.
//
// Scale: a lease or a completion touches the job record, one task record and a few
// sorted-set entries; only opening a stage touches that stage's tasks (they all become
// queued), and ending a job early (fail, cancel) its unfinished tasks. Job.phases is kept
// as counters of the latest round.
//
// The scripts build key names from the prefix (keys.go) because a lease discovers the
// keys it needs while it runs; on Redis Cluster the prefix must therefore be a hash tag
// such as "{farm}:" so that all of a farm's keys share a slot.
package redisstore

import (
	"context"
	"crypto/rand"
	"encoding/hex"
	"errors"
	"fmt"
	"strconv"
	"strings"
	"time"

	"github.com/redis/go-redis/v9"

	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// Store is a store.Store over Redis. Create it with New.
type Store struct {
	rdb    redis.UniversalClient
	prefix string
	opts   store.Options
	rounds roundCache
	// ops is the head of this Store value's operation keys, "op:" and its origin, so
	// that Follow can tell its own changes from other replicas'.
	ops string
}

var _ store.Store = (*Store)(nil)

// New returns a Store keeping its keys under prefix in the Redis rdb talks to. It checks
// that Redis answers and loads the scripts; the data already under prefix (a restarted coordinator's) is used
// as it is.
func New(ctx context.Context, rdb redis.UniversalClient, prefix string, opts store.Options) (*Store, error) {
	if err := rdb.Ping(ctx).Err(); err != nil {
		return nil, fmt.Errorf("redisstore: %w", err)
	}
	if err := checkLayout(ctx, rdb, prefix); err != nil {
		return nil, err
	}
	// Loaded now, the scripts are called by their digest from the first call on (a Redis
	// that lost them, restarted without its data, gets them again: redis.Script.Run).
	for _, sc := range scripts {
		if err := sc.Load(ctx, rdb).Err(); err != nil {
			return nil, fmt.Errorf("redisstore: load scripts: %w", err)
		}
	}
	var origin [8]byte
	_, _ = rand.Read(origin[:])
	return &Store{rdb: rdb, prefix: prefix, opts: opts.WithDefaults(), ops: prefix + opPrefix + hex.EncodeToString(origin[:]) + "."}, nil
}

// layoutVersion names the key layout of keys.go and scripts.go. Version 2 (issue 12: stages
// as ranges, jobs made in chunks, lease sets, operations) cannot read jobs the scripts of
// version 1 wrote, which had no layout key.
const layoutVersion = "2"

// checkLayout records the layout under an empty prefix and refuses a prefix whose keys are
// of another layout, rather than fail in the middle of its jobs.
func checkLayout(ctx context.Context, rdb redis.UniversalClient, prefix string) error {
	v, err := rdb.Eval(ctx, `
local v = redis.call('GET', KEYS[1])
if v then return v end
if redis.call('EXISTS', KEYS[2]) == 1 then return '1' end
redis.call('SET', KEYS[1], ARGV[1])
return ARGV[1]`, []string{prefix + layoutKey, prefix + seqKey}, layoutVersion).Text()
	if err != nil {
		return fmt.Errorf("redisstore: %w", err)
	}
	if v != layoutVersion {
		return fmt.Errorf("redisstore: the keys under prefix %q are of layout %s, this coordinator's are of layout %s: finish their jobs with the coordinator that made them, or use another prefix", prefix, v, layoutVersion)
	}
	return nil
}

// An operation's answer is kept for OpTTL (scripts.go, Operations); run retries a call
// whose outcome it does not know for at most RetryWindow, well within it.
const (
	OpTTL       = 2 * time.Minute
	RetryWindow = time.Minute
)

// run runs a script as one operation (scripts.go, Operations), with the prefix and the time
// in front of args. A failure that leaves the outcome unknown (the connection lost, a
// timeout, Redis busy or loading) is retried with the same operation key until Redis
// answers, so that the answer is that of the one run; past RetryWindow or ctx, run
// reports Unavailable, saying the outcome is unknown.
func (s *Store) run(ctx context.Context, sc *redis.Script, args ...any) (any, error) {
	args = append([]any{s.prefix, micros(s.opts.Clock.Now())}, args...)
	var token [16]byte
	_, _ = rand.Read(token[:])
	keys := []string{s.key(jobsKey), s.ops + hex.EncodeToString(token[:])}
	start := time.Now()
	for attempt := 0; ; attempt++ {
		v, err := sc.Run(ctx, s.rdb, keys, args...).Result()
		if err == nil {
			return v, nil
		}
		if !unknownOutcome(err) {
			return nil, redisErr(err)
		}
		wait := min(10*time.Millisecond<<min(attempt, 7), time.Second)
		if ctx.Err() != nil || time.Since(start)+wait > RetryWindow {
			return nil, errs.Wrap(errs.Unavailable, err, "redis (the outcome is unknown; a retry of the same request is safe)")
		}
		select {
		case <-time.After(wait):
		case <-ctx.Done():
		}
	}
}

// unknownOutcome reports whether a failed call may or may not have run: any failure but
// an error Redis answered the script with, or answers Redis gives before running
// anything (busy with another script, loading its data, a replica or cluster not ready).
func unknownOutcome(err error) bool {
	var answered redis.Error
	if !errors.As(err, &answered) {
		return !errors.Is(err, context.Canceled) && !errors.Is(err, context.DeadlineExceeded)
	}
	msg := answered.Error()
	for _, p := range []string{"BUSY", "LOADING", "TRYAGAIN", "MASTERDOWN", "READONLY", "CLUSTERDOWN"} {
		if strings.HasPrefix(msg, p) {
			return true
		}
	}
	return false
}

// change runs a script that answers with one reply.
func (s *Store) change(ctx context.Context, sc *redis.Script, args ...any) (reply, error) {
	v, err := s.run(ctx, sc, args...)
	if err != nil {
		return reply{}, err
	}
	return s.decodeReply(ctx, v)
}

// changes runs a script that answers with a list of replies.
func (s *Store) changes(ctx context.Context, sc *redis.Script, args ...any) ([]store.Change, error) {
	v, err := s.run(ctx, sc, args...)
	if err != nil {
		return nil, err
	}
	l, _ := v.([]any)
	return s.decodeChanges(ctx, l)
}

func (s *Store) decodeChanges(ctx context.Context, l []any) ([]store.Change, error) {
	var out []store.Change
	for _, x := range l {
		r, err := s.decodeReply(ctx, x)
		if err != nil {
			return nil, err
		}
		out = append(out, r.change)
	}
	return out, nil
}

// redisErr reports a failed Redis call: unreachable Redis means the store cannot
// answer now; an error Redis answered with (a failing script) is a bug.
func redisErr(err error) error {
	var answered redis.Error
	if errors.As(err, &answered) {
		return errs.Wrap(errs.Internal, err, "redis")
	}
	return errs.Wrap(errs.Unavailable, err, "redis")
}

// GetJob implements store.Store.
func (s *Store) GetJob(ctx context.Context, jobID string) (*pb.Job, error) {
	jobs, err := s.jobs(ctx, []string{jobID})
	if err != nil {
		return nil, err
	}
	return jobs[0], nil
}

// jobs reads jobs, each record with one HGETALL (pipelined), and their round reports.
func (s *Store) jobs(ctx context.Context, ids []string) ([]*pb.Job, error) {
	cmds := make([]*redis.MapStringStringCmd, len(ids))
	_, err := s.rdb.Pipelined(ctx, func(p redis.Pipeliner) error {
		for i, id := range ids {
			cmds[i] = p.HGetAll(ctx, s.jobKey(id))
		}
		return nil
	})
	if err != nil {
		return nil, redisErr(err)
	}
	records := make([]map[string]string, len(ids))
	for i, id := range ids {
		if records[i] = cmds[i].Val(); len(records[i]) == 0 || !visible(records[i]) {
			return nil, noJob(id)
		}
	}
	return s.decodeJobs(ctx, records)
}

// visible reports whether a job record is one a read may see: not still being created
// (scripts.go, beginScript) nor being deleted (purgeScript).
func visible(h map[string]string) bool { return h["building"] == "" && h["doomed"] == "" }

func noJob(id string) error {
	return &errs.Error{Kind: errs.NotFound, Field: "job_id", Message: fmt.Sprintf("no job %q", id)}
}

// view reads what the state of a job's tasks depends on, and how many it has; NotFound
// for an unknown job.
func (s *Store) view(ctx context.Context, jobID string) (jobView, uint64, error) {
	fields := []string{"state", "cur", "curend", "ntasks", "building", "doomed"}
	v, err := s.rdb.HMGet(ctx, s.jobKey(jobID), fields...).Result()
	if err != nil {
		return jobView{}, 0, redisErr(err)
	}
	h := map[string]string{}
	for i, f := range fields {
		h[f], _ = v[i].(string)
	}
	if h["state"] == "" || !visible(h) {
		return jobView{}, 0, noJob(jobID)
	}
	return viewOf(h), number(h["ntasks"]), nil
}

// GetTask implements store.Store.
func (s *Store) GetTask(ctx context.Context, taskID string) (*pb.Task, error) {
	h, err := s.rdb.HGetAll(ctx, s.taskKey(taskID)).Result()
	if err != nil {
		return nil, redisErr(err)
	}
	if len(h) == 0 {
		return nil, &errs.Error{Kind: errs.NotFound, Field: "task_id", Message: fmt.Sprintf("no task %q", taskID)}
	}
	v, _, err := s.view(ctx, h["job"])
	if err != nil {
		return nil, err
	}
	return decodeTask(h, v)
}

// ListJobs implements store.Store.
func (s *Store) ListJobs(ctx context.Context, pageSize int, pageToken string) ([]*pb.Job, string, error) {
	before, given, err := store.Page('j', pageSize, pageToken)
	if err != nil {
		return nil, "", err
	}
	upper := "+inf"
	if given {
		upper = "(" + strconv.FormatUint(before, 10)
	}
	// One more than a page tells whether another page follows.
	zs, err := s.rdb.ZRevRangeByScoreWithScores(ctx, s.key(jobsKey), &redis.ZRangeBy{
		Max: upper, Min: "-inf", Count: int64(pageSize) + 1,
	}).Result()
	if err != nil {
		return nil, "", redisErr(err)
	}
	next := ""
	if len(zs) > pageSize {
		zs = zs[:pageSize]
		next = store.EncodePageToken('j', uint64(zs[pageSize-1].Score))
	}
	ids := make([]string, len(zs))
	for i, z := range zs {
		ids[i], _ = z.Member.(string)
	}
	jobs, err := s.jobs(ctx, ids)
	if err != nil {
		return nil, "", err
	}
	return jobs, next, nil
}

// ListTasks implements store.Store.
func (s *Store) ListTasks(ctx context.Context, jobID string, pageSize int, pageToken string) ([]*pb.Task, string, error) {
	from, _, err := store.Page('t', pageSize, pageToken)
	if err != nil {
		return nil, "", err
	}
	v, n, err := s.view(ctx, jobID)
	if err != nil {
		return nil, "", err
	}
	to, next := min(from+uint64(pageSize), n), ""
	if to < n {
		next = store.EncodePageToken('t', to)
	}
	if from >= to {
		return nil, next, nil
	}
	// Tasks are only ever added, so the n read above still bounds them. A plain pipeline,
	// not MULTI: Redis serves other clients between its commands, where it would run a
	// transaction of a page of 10,000 records without a pause.
	cmds := make([]*redis.MapStringStringCmd, 0, to-from)
	_, err = s.rdb.Pipelined(ctx, func(p redis.Pipeliner) error {
		for i := from; i < to; i++ {
			cmds = append(cmds, p.HGetAll(ctx, s.taskKey(store.TaskID(jobID, uint32(i)))))
		}
		return nil
	})
	if err != nil {
		return nil, "", redisErr(err)
	}
	out := make([]*pb.Task, len(cmds))
	for i, c := range cmds {
		if out[i], err = decodeTask(c.Val(), v); err != nil {
			return nil, "", err
		}
	}
	return out, next, nil
}

// Ping reports whether Redis answers, for the coordinator's health service.
func (s *Store) Ping(ctx context.Context) error {
	if err := s.rdb.Ping(ctx).Err(); err != nil {
		return fmt.Errorf("redisstore: %w", err)
	}
	return nil
}
