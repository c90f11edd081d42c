package redisstore

import (
	"context"
	"slices"
	"strconv"
	"time"

	"github.com/redis/go-redis/v9"

	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// Workers is the store.Workers kept in Redis next to the jobs, so that every coordinator
// replica on one Redis lists the same workers and knows those that registered with
// another. A worker is the hash w:{id} (seq, host, cores, ver, reg and seen in µs, cur, done,
// failed) and its places in two sorted sets, by registration (workers) and by when it was
// last heard from (seen), so that listing, finding the live ones and forgetting the
// silent ones read a range instead of scanning; the latest holder of each lease is in
// holders. Each change is one script, so replicas never see half of one.
type Workers struct{ s *Store }

var _ store.Workers = (*Workers)(nil)

// Workers returns the registry kept under the Store's prefix.
func (s *Store) Workers() *Workers { return &Workers{s: s} }

// forgetBatch is how many silent workers one script forgets.
const forgetBatch = 1000

// run runs a registry script with the prefix and now in front of args.
func (r *Workers) run(ctx context.Context, sc *redis.Script, now time.Time, args ...any) (any, error) {
	args = append([]any{r.s.prefix, micros(now)}, args...)
	v, err := sc.Run(ctx, r.s.rdb, []string{r.s.key(workersKey)}, args...).Result()
	if err != nil && err != redis.Nil {
		return nil, redisErr(err)
	}
	return v, nil
}

// Add implements store.Workers.
func (r *Workers) Add(ctx context.Context, w store.Worker, lost time.Duration) error {
	v, err := r.run(ctx, addWorkerScript, w.Registered, w.ID, w.Hostname, w.Cores, w.Version,
		micros(w.Registered.Add(-lost)), store.MaxWorkers)
	if err != nil {
		return err
	}
	if v != int64(1) {
		return store.RegistryFull()
	}
	return nil
}

// Touch implements store.Workers.
func (r *Workers) Touch(ctx context.Context, id string, now time.Time) error {
	v, err := r.run(ctx, touchWorkerScript, now, id)
	if err != nil {
		return err
	}
	if v != int64(1) {
		return store.UnknownWorker(id, true)
	}
	return nil
}

// Leased implements store.Workers.
func (r *Workers) Leased(ctx context.Context, id, taskID string) error {
	_, err := r.run(ctx, leasedWorkerScript, time.Time{}, id, taskID)
	return err
}

// Ended implements store.Workers.
func (r *Workers) Ended(ctx context.Context, id, taskID string, ok bool) error {
	outcome := "0"
	if ok {
		outcome = "1"
	}
	_, err := r.run(ctx, endedWorkerScript, time.Time{}, id, taskID, outcome)
	return err
}

// Dropped implements store.Workers.
func (r *Workers) Dropped(ctx context.Context, id, taskID string) error {
	_, err := r.run(ctx, droppedWorkerScript, time.Time{}, id, taskID)
	return err
}

// Expired implements store.Workers.
func (r *Workers) Expired(ctx context.Context, taskID string) error {
	_, err := r.run(ctx, expiredWorkerScript, time.Time{}, taskID)
	return err
}

// List implements store.Workers.
func (r *Workers) List(ctx context.Context, now time.Time, lost time.Duration, n int, token string) ([]*pb.WorkerInfo, string, error) {
	after, _, err := store.Page(store.WorkerPageToken, n, token)
	if err != nil {
		return nil, "", err
	}
	v, err := r.run(ctx, listWorkersScript, now, strconv.FormatUint(after, 10), n+1)
	if err != nil {
		return nil, "", err
	}
	l, _ := v.([]any)
	ws := make([]store.Worker, 0, len(l))
	for _, x := range l {
		if pair, _ := x.([]any); len(pair) == 2 {
			id, _ := pair[0].(string)
			ws = append(ws, decodeWorker(id, hash(pair[1])))
		}
	}
	out, next := store.WorkersPage(ws, n, now, lost)
	return out, next, nil
}

// decodeWorker rebuilds a registration from its hash.
func decodeWorker(id string, h map[string]string) store.Worker {
	us := func(f string) time.Time { n, _ := strconv.ParseInt(h[f], 10, 64); return time.UnixMicro(n) }
	return store.Worker{
		ID: id, Hostname: h["host"], Version: h["ver"], Cores: uint32(number(h["cores"])),
		Seq: number(h["seq"]), Registered: us("reg"), LastSeen: us("seen"), Current: h["cur"],
		Done: number(h["done"]), Failed: number(h["failed"]),
	}
}

// Live implements store.Workers.
func (r *Workers) Live(ctx context.Context, now time.Time, lost time.Duration) ([]string, error) {
	ids, err := r.s.rdb.ZRangeByScore(ctx, r.s.key(seenKey), &redis.ZRangeBy{Min: micros(now.Add(-lost)), Max: "+inf"}).Result()
	if err != nil {
		return nil, redisErr(err)
	}
	slices.Sort(ids)
	return ids, nil
}

// Remove implements store.Workers.
func (r *Workers) Remove(ctx context.Context, id string) error {
	v, err := r.run(ctx, removeWorkerScript, time.Time{}, id)
	if err != nil {
		return err
	}
	if v != int64(1) {
		return store.UnknownWorker(id, false)
	}
	return nil
}

// ForgetSilent implements store.Workers, forgetBatch workers a script.
func (r *Workers) ForgetSilent(ctx context.Context, now time.Time, after time.Duration) (int, error) {
	total := 0
	for {
		v, err := r.run(ctx, forgetSilentScript, now, micros(now.Add(-after)), forgetBatch)
		if err != nil {
			return total, err
		}
		n, _ := v.(int64)
		total += int(n)
		if n < forgetBatch {
			return total, nil
		}
	}
}

// The registry's scripts: ARGV[1] the prefix, [2] now (µs), then their own arguments
// (named in each). A worker unknown to the registry (the coordinator's builder, or one
// forgotten) is left alone.
const workersLib = `
local function known(id) return redis.call('EXISTS', wkey(id)) == 1 end

-- release: id no longer holds t's lease.
local function release(id, t)
  if redis.call('HGET', wkey(id), 'cur') == t then redis.call('HDEL', wkey(id), 'cur') end
  if redis.call('HGET', HOLDERS, t) == id then redis.call('HDEL', HOLDERS, t) end
end

-- count: id's attempt at t ended, ok ('1') or not.
local function count(id, t, ok)
  redis.call('HINCRBY', wkey(id), ok == '1' and 'done' or 'failed', 1)
  release(id, t)
end

local function forget(id)
  local cur = redis.call('HGET', wkey(id), 'cur')
  if cur and redis.call('HGET', HOLDERS, cur) == id then redis.call('HDEL', HOLDERS, cur) end
  redis.call('DEL', wkey(id))
  redis.call('ZREM', WORKERS, id)
  redis.call('ZREM', SEEN, id)
end
`

func newWorkersScript(body string) *redis.Script {
	sc := redis.NewScript(preamble + workersLib + body)
	scripts = append(scripts, sc)
	return sc
}

// addWorkerScript: [3] id, [4] hostname, [5] cores, [6] version, [7] the time (µs) before
// which a worker last heard from is lost, [8] MaxWorkers. 1, or 0 if full of live workers.
var addWorkerScript = newWorkersScript(`
local id = ARGV[3]
if redis.call('ZCARD', WORKERS) >= tonumber(ARGV[8]) then
  local oldest = redis.call('ZRANGEBYSCORE', SEEN, '-inf', '(' .. ARGV[7], 'LIMIT', 0, 1)
  if #oldest == 0 then return 0 end
  forget(oldest[1])
end
local seq = redis.call('INCR', WSEQ)
redis.call('HSET', wkey(id), 'seq', seq, 'host', ARGV[4], 'cores', ARGV[5], 'ver', ARGV[6], 'reg', NOW_S, 'seen', NOW_S, 'done', 0, 'failed', 0)
redis.call('ZADD', WORKERS, seq, id)
redis.call('ZADD', SEEN, NOW_S, id)
return 1
`)

// touchWorkerScript: [3] id. 1, or 0 for an unknown worker.
var touchWorkerScript = newWorkersScript(`
if not known(ARGV[3]) then return 0 end
redis.call('HSET', wkey(ARGV[3]), 'seen', NOW_S)
redis.call('ZADD', SEEN, NOW_S, ARGV[3])
return 1
`)

// leasedWorkerScript: [3] id, [4] task id.
var leasedWorkerScript = newWorkersScript(`
if known(ARGV[3]) then
  redis.call('HSET', wkey(ARGV[3]), 'cur', ARGV[4])
  redis.call('HSET', HOLDERS, ARGV[4], ARGV[3])
end
return 1
`)

// endedWorkerScript: [3] id, [4] task id, [5] '1' if it succeeded.
var endedWorkerScript = newWorkersScript(`
if known(ARGV[3]) then count(ARGV[3], ARGV[4], ARGV[5]) end
return 1
`)

// droppedWorkerScript: [3] id, [4] task id.
var droppedWorkerScript = newWorkersScript(`
if known(ARGV[3]) then release(ARGV[3], ARGV[4]) end
return 1
`)

// expiredWorkerScript: [3] task id; its latest holder failed it.
var expiredWorkerScript = newWorkersScript(`
local id = redis.call('HGET', HOLDERS, ARGV[3])
if id and known(id) then count(id, ARGV[3], '0') end
return 1
`)

// listWorkersScript: [3] the sequence after which to list, [4] how many. {{id, HGETALL}...}.
var listWorkersScript = newWorkersScript(`
local out = {}
for i, id in ipairs(redis.call('ZRANGEBYSCORE', WORKERS, '(' .. ARGV[3], '+inf', 'LIMIT', 0, tonumber(ARGV[4]))) do
  out[i] = {id, redis.call('HGETALL', wkey(id))}
end
return out
`)

// removeWorkerScript: [3] id. 1, or 0 for an unknown worker.
var removeWorkerScript = newWorkersScript(`
if not known(ARGV[3]) then return 0 end
forget(ARGV[3])
return 1
`)

// forgetSilentScript: [3] the time (µs) before which a worker last heard from is
// forgotten, [4] at most how many. How many it forgot.
var forgetSilentScript = newWorkersScript(`
local ids = redis.call('ZRANGEBYSCORE', SEEN, '-inf', '(' .. ARGV[3], 'LIMIT', 0, tonumber(ARGV[4]))
for _, id in ipairs(ids) do forget(id) end
return #ids
`)
