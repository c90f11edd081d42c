package redisstore

import (
	"strconv"

	"github.com/redis/go-redis/v9"
)

// Every script gets ARGV[1] = the key prefix and ARGV[2] = now (Unix microseconds, from
// Options.Clock), then its own arguments. KEYS[1] is the prefix's "jobs" key and only
// routes the call; KEYS[2] is the call's operation key (below); the scripts build the
// other keys from the prefix with the functions
// the preamble (preamble.go) declares from keys.go, and name task and job states by the
// preamble's locals (WAITING ... CANCELLED, JQUEUED ... JCANCELLED).
//
// Times and epochs are stored as the strings Go sent and compared with tonumber:
// microseconds since 1970 stay below 2^53, so the comparison is exact, while Lua would
// print such a number with only 14 digits.
//
// Scripts that change a task or a job answer through ok(): {"OK", jobStateChanged,
// queued, HGETALL job, HGETALL task}; a refusal is {"E", kind, field, message}; a
// repeated report is {"NOOP"}.
//
// Operations: a call whose answer is lost (the connection dropped after Redis ran the
// script, a read timeout) may be sent again, by go-redis's retries or by Store.run, and
// must then get the answer of the first run, not run again: a second CreateJob would
// make a second job, a second FailTask find the lease gone. Each call carries a fresh
// operation key (KEYS[2], "op:{token}"); the first run keeps its answer's skeleton there
// for OpTTL (ok() answers {"OK", changed, queued, job id, task id}, and render expands it
// to the records as they stand), and a run that finds the key answers from it.
//
// Stages: the tasks of a job's current stage [cur, curend) are one phase (cphase); those
// never leased since it opened are the range [next, curend), so opening a stage writes no
// task record, and those that went back to the queue (released, expired, out of their
// backoff) are the members of q:{job}:{phase}. A task record keeps the state it was last
// given: a WAITING task inside the current stage is QUEUED, and any unfinished task of an
// ended job is CANCELLED (codec.go's taskState), so that ending a job touches its leases,
// not its tasks. Every script's work is bounded by its own arguments and the leases it
// touches, never by the tasks of a job.
//
// Scheduling (store package comment): a job with leasable tasks of its current stage's
// phase is a member of ready:{phase} (see place), scored (1000 - priority)·2^32 + leases
// held, so the lowest score is the highest priority and then the fewest leases held; the
// member is the job's sequence zero-padded, ":" and its id, so that equal scores, which
// Redis orders by member, go oldest first. Every step that changes a job's held leases,
// priority or queue calls place, so a lease reads the best job from the head of a sorted
// set (O(log jobs)) rather than scanning the jobs. The one per-worker condition, the
// blocklist, is checked on the head members until one has not blocked the caller: a
// worker is blocked from few jobs. Tasks in backoff wait in the delayed set, outside
// their job's queue, so they never hide a leasable job; each lease first moves the due
// ones back (promote, a bounded number a call).
const lib = `
local function tid(jid, i) return jid .. '.' .. i end
local function num(key, field) return tonumber(redis.call('HGET', key, field) or '0') end

local function refuse(kind, field, msg) return {'E', kind, field, msg} end

local function ended(st) return st == JSUCCEEDED or st == JFAILED or st == JCANCELLED end

-- unknown refuses a job that does not exist, or no longer: it is being deleted
-- (purgeScript) or was never finished (beginScript).
local function unknown(jid)
  local h = redis.call('HMGET', jkey(jid), 'state', 'doomed', 'building')
  if not h[1] or h[2] or h[3] then return refuse('notfound', 'job_id', 'no job "' .. jid .. '"') end
  return nil
end

-- live refuses a job that does not exist or has ended.
local function live(jid)
  local e = unknown(jid)
  if e then return e end
  local st = redis.call('HGET', jkey(jid), 'state')
  st = tonumber(st)
  if ended(st) then
    return refuse('precondition', '', 'job ' .. jid .. ' has already ended (JOB_STATE_' .. JOB_STATES[st] .. ')')
  end
  return nil
end

-- policy parses the retry policy Go sends as "attempts block base cap" (Store.policy).
local function policy(s)
  local v = {}
  for n in string.gmatch(s, '%d+') do v[#v + 1] = tonumber(n) end
  return {attempts = v[1], block = v[2], base = v[3], cap = v[4]}
end

-- greater compares two decimal strings without leading zeros (uint64 progress, which a
-- double would round).
local function greater(a, b) return #a > #b or (#a == #b and a > b) end

local function jobof(member) return string.match(member, ':(.*)$') end

-- place puts the job in the ready set of its current stage's phase, ranked by priority
-- and leases held, or takes it out when that phase has no leasable task or the job has
-- ended. (A stage's phase only changes when the stage before has nothing left to lease,
-- so the job is then in no ready set.)
local function place(jid)
  local jk = jkey(jid)
  local h = redis.call('HMGET', jk, 'seq', 'prio', 'held', 'cphase', 'next', 'curend', 'state')
  local phase = h[4]
  local member = string.rep('0', 16 - #h[1]) .. h[1] .. ':' .. jid
  if not ended(tonumber(h[7])) and (tonumber(h[5]) < tonumber(h[6]) or redis.call('EXISTS', qkey(jid, phase)) == 1) then
    redis.call('ZADD', readykey(phase), (1000 - tonumber(h[2] or '0')) * 4294967296 + tonumber(h[3] or '0'), member)
  else
    redis.call('ZREM', readykey(phase), member)
  end
end

-- unlease ends t's lease: it leaves LEASES and its job's leases (lkey), and the job holds
-- one lease less.
local function unlease(t, jid)
  redis.call('ZREM', LEASES, t)
  redis.call('SREM', lkey(jid), t)
  redis.call('HINCRBY', jkey(jid), 'held', -1)
end

-- ok is the skeleton of a change's answer (see Operations); render expands it. The same
-- skeleton goes into the feed (feed.go) in the same script, so no change is stored without
-- reaching the other replicas, whatever happens to the coordinator that made it; 'b' says
-- whether the job has ever blocked a worker (its bkind is set), which followers track.
local function ok(changed, queued, jid, t)
  redis.call('XADD', CHANGES, 'MAXLEN', '~', FEED_LENGTH, '*', 'o', KEYS[2], 'c', changed, 'q', queued, 'j', jid, 't', t or '',
    'b', redis.call('HEXISTS', jkey(jid), 'bkind'))
  return {'OK', changed, queued, jid, t or ''}
end

local function render(r)
  if type(r) ~= 'table' then return r end
  if r[1] == 'OK' then
    local task = {}
    if r[5] ~= '' then task = redis.call('HGETALL', tkey(r[5])) end
    return {'OK', r[2], r[3], redis.call('HGETALL', jkey(r[4])), task}
  end
  local out = {}
  for i, x in ipairs(r) do out[i] = render(x) end
  return out
end

-- held refuses a report unless (worker, epoch) holds t's live lease. The lease of a task
-- of an ended job was cancelled with it.
local function held(t, worker, epoch)
  local h = redis.call('HMGET', tkey(t), 'epoch', 'worker', 'state', 'expire', 'job')
  if not h[3] then return refuse('notfound', 'task_id', 'no task "' .. t .. '"') end
  local pre = 'task ' .. t .. ': lease epoch ' .. epoch
  local cur = h[1] or '0'
  if cur ~= epoch then return refuse('precondition', '', pre .. ' is retired (current epoch ' .. cur .. ')') end
  if h[2] ~= worker then return refuse('precondition', '', pre .. ' is held by another worker, not ' .. worker) end
  local st = tonumber(h[3])
  if st == LEASED and ended(tonumber(redis.call('HGET', jkey(h[5]), 'state'))) then st = CANCELLED end
  if st ~= LEASED then return refuse('precondition', '', pre .. ' is no longer held (task is TASK_STATE_' .. TASK_STATES[st] .. ')') end
  if NOW >= tonumber(h[4]) then return refuse('precondition', '', pre .. ' expired') end
  return nil
end

-- repeated: t already succeeded under this very lease, so the report was accepted before.
local function repeated(t, worker, epoch)
  local h = redis.call('HMGET', tkey(t), 'state', 'epoch', 'worker')
  return tonumber(h[1]) == SUCCEEDED and h[2] == epoch and h[3] == worker
end

-- again answers a repeat of t's accepted report: NOOP if its outputs (and, for a round's
-- composite, metrics) are those recorded, else a refusal naming what differs
-- (store.ConflictingReport).
local function again(t, epoch, outputs, metrics)
  local h = redis.call('HMGET', tkey(t), 'outputs', 'metrics')
  local what
  if h[1] ~= outputs then what = 'outputs' elseif metrics and (h[2] or '') ~= metrics then what = 'metrics' end
  if not what then return {'NOOP'} end
  return refuse('precondition', '', 'task ' .. t .. ': lease epoch ' .. epoch .. ' was already completed with other ' .. what ..
    '; a repeated report must be the same')
end

-- openstage queues the stage starting at task index start and makes it the current one:
-- its tasks are the range [next, curend), none is written.
local function openstage(jid, start)
  local stop = tonumber(redis.call('HGET', skey(jid), start))
  local phase = redis.call('HGET', tkey(tid(jid, start)), 'phase')
  redis.call('HSET', jkey(jid), 'cur', start, 'curend', stop, 'next', start, 'left', stop - start, 'cphase', phase)
  place(jid)
end

-- addtasks makes the new tasks of a job known: ntasks grows to top, their stages are
-- ranges (stages: "start:end,...") and the progress counters those of their last round
-- (counts: "phase:total,..." in plan order; both from Go's summary), and their first
-- stage, at base, is queued. Their records were staged before (stageScript).
local function addtasks(jid, base, top, stages, counts, round)
  local jk = jkey(jid)
  for ph in string.gmatch(redis.call('HGET', jk, 'pphases') or '', '%d+') do
    redis.call('HDEL', jk, 'pt:' .. ph, 'ps:' .. ph)
  end
  local plist = {}
  for ph, n in string.gmatch(counts, '(%d+):(%d+)') do
    plist[#plist + 1] = ph
    redis.call('HSET', jk, 'pt:' .. ph, n)
  end
  for a, b in string.gmatch(stages, '(%d+):(%d+)') do redis.call('HSET', skey(jid), a, b) end
  redis.call('HSET', jk, 'ntasks', top, 'pphases', table.concat(plist, ','), 'pround', round)
  redis.call('HDEL', jk, 'sowner', 'stop')
  openstage(jid, base)
end

-- requeue puts a leased task back in its job's queue, or, given retry (µs), in DELAYED
-- until then; it returns the job id.
local function requeue(t, retry)
  local k = tkey(t)
  local h = redis.call('HMGET', k, 'job', 'idx', 'phase')
  unlease(t, h[1])
  redis.call('HSET', k, 'state', QUEUED, 'worker', '')
  if retry then
    redis.call('HSET', k, 'retry', retry)
    redis.call('ZADD', DELAYED, retry, t)
  else
    redis.call('ZADD', qkey(h[1], h[3]), h[2], h[2])
  end
  place(h[1])
  redis.call('HSET', jkey(h[1]), 'update', NOW_S)
  return h[1]
end

-- promote queues up to PROMOTE_BATCH (Go's PromoteBatch) of the delayed tasks whose
-- backoff has ended (the others go at the next leases), dropping those whose job has
-- ended or gone.
local function promote()
  for _, t in ipairs(redis.call('ZRANGEBYSCORE', DELAYED, '-inf', NOW_S, 'LIMIT', 0, PROMOTE_BATCH)) do
    redis.call('ZREM', DELAYED, t)
    local h = redis.call('HMGET', tkey(t), 'job', 'idx', 'phase')
    if h[1] and not ended(tonumber(redis.call('HGET', jkey(h[1]), 'state'))) then
      redis.call('ZADD', qkey(h[1], h[3]), h[2], h[2])
      place(h[1])
    end
  end
end

-- succeed records a task's success and its round's progress; it returns the job id.
local function succeed(t, outputs)
  local k = tkey(t)
  redis.call('HSET', k, 'state', SUCCEEDED, 'outputs', outputs)
  local h = redis.call('HMGET', k, 'job', 'round', 'phase')
  unlease(t, h[1])
  place(h[1])
  local jk = jkey(h[1])
  redis.call('HSET', jk, 'update', NOW_S)
  if redis.call('HGET', jk, 'pround') == h[2] then redis.call('HINCRBY', jk, 'ps:' .. h[3], 1) end
  return h[1]
end

local function succeedjob(jid, outputs)
  redis.call('HSET', jkey(jid), 'state', JSUCCEEDED, 'end', NOW_S, 'outputs', outputs)
  redis.call('ZADD', ENDED, NOW_S, jid)
end

-- endjob moves a job to a terminal state (with why and the failure kind for JFAILED),
-- empties its queue and cancels its leases; its unfinished tasks read as CANCELLED from
-- now on, and its delayed ones are dropped when due (promote).
local function endjob(jid, state, msg, kind)
  local jk = jkey(jid)
  redis.call('HSET', jk, 'state', state, 'error', msg, 'fkind', kind, 'end', NOW_S, 'update', NOW_S, 'held', 0)
  redis.call('ZADD', ENDED, NOW_S, jid)
  redis.call('DEL', qkey(jid, redis.call('HGET', jk, 'cphase')))
  for _, t in ipairs(redis.call('SMEMBERS', lkey(jid))) do redis.call('ZREM', LEASES, t) end
  redis.call('DEL', lkey(jid))
  place(jid)
end

-- doom marks a job for deletion: no read sees it from then on, its request id is
-- forgotten, and purgeScript deletes its records (the field doomed counts those left).
local function doom(jid)
  local jk = jkey(jid)
  local h = redis.call('HMGET', jk, 'req', 'ntasks', 'stop')
  redis.call('ZREM', JOBS, jid)
  redis.call('ZREM', ENDED, jid)
  redis.call('ZREM', PENDING, jid)
  if h[1] and h[1] ~= '' and redis.call('HGET', REQUESTS, h[1]) == jid then redis.call('HDEL', REQUESTS, h[1]) end
  redis.call('HSET', jk, 'doomed', math.max(tonumber(h[2] or '0'), tonumber(h[3] or '0')))
  redis.call('ZADD', DOOMED, NOW_S, jid)
end

-- failjob fails leased task t and its job with msg, of the kind of t's last failure.
local function failjob(t, jid, msg)
  local k = tkey(t)
  redis.call('HSET', k, 'state', FAILED)
  unlease(t, jid)
  endjob(jid, JFAILED, msg, redis.call('HGET', k, 'fkind'))
  return ok(1, 0, jid, t)
end

-- limitfailure is the job's error when t reached a limit after n failures
-- (store.JobFailure).
local function limitfailure(t, n)
  return 'task ' .. t .. ' failed ' .. n .. ' times; last error: ' .. redis.call('HGET', tkey(t), 'error')
end

-- fail counts a transient failed attempt of kind at t's live lease by worker (FailTask,
-- a stuck lease) under pol (policy): unless kind is one of SPARES, the worker is blocked
-- from the job at pol.block failures (reason as store.BlockReason, stored as "µs reason"; the kind as the job's
-- bkind); the task goes back after store.Options.Backoff, or at pol.attempts fails with
-- its job.
local function fail(t, worker, msg, pol, kind)
  local k = tkey(t)
  local jid = redis.call('HGET', k, 'job')
  local jk = jkey(jid)
  local failures = redis.call('HINCRBY', k, 'failures', 1)
  redis.call('HSET', k, 'error', msg, 'fkind', kind)
  if not SPARES[tonumber(kind)] then
    local n = redis.call('HINCRBY', jk, FAILURES .. worker, 1)
    if n >= pol.block and redis.call('HEXISTS', jk, BLOCKED .. worker) == 0 then
      redis.call('HSET', jk, BLOCKED .. worker, NOW_S .. ' ' .. n .. ' failed tasks: ' .. msg, 'bkind', kind)
    end
  end
  if failures >= pol.attempts then return failjob(t, jid, limitfailure(t, failures)) end
  local retry = string.format('%.0f', NOW + math.min(pol.base * 2 ^ (failures - 1), pol.cap))
  return ok(0, 0, requeue(t, retry), t)
end
`

// A job is created in bounded steps, so that Redis serves everyone else in between:
// beginScript writes its record (flagged "building": no listing, read or lease sees it)
// and puts it in PENDING; stageScript writes a chunk of task records at a time; and
// publishScript makes it a job in one step: numbered, listed, its first stage queued.
// CompleteRound stages the next round's tasks the same way (beyond ntasks, where nothing
// reads them) before completeRoundScript appends them in one step. A coordinator that dies
// midway leaves a half-made job in PENDING (score: when it last grew): a retry of the
// submission with the same request id finishes it (planning is deterministic, and a stage
// already written is skipped), and otherwise the purge deletes it (PurgeJobs). Staged
// records of a round whose composite was not completed are rewritten when the redone
// composite stages its next round, or deleted with the job.

// beginScript: ARGV[3] job id, [4] request id, [5] the job's static record, [6] its
// priority, [7] its number of tasks, [8] its scene digest. A request id seen before
// answers with the job it created ({'BUILD', id} if that one is still being made: the
// caller carries on making it, which must be from the same scene).
var beginScript = newScript(`
local jid, req = ARGV[3], ARGV[4]
if req ~= '' then
  local old = redis.call('HGET', REQUESTS, req)
  if old then
    local h = redis.call('HMGET', jkey(old), 'building', 'total', 'digest')
    if not h[1] then return ok(0, 0, old, nil) end
    if h[2] ~= ARGV[7] or h[3] ~= ARGV[8] then
      return refuse('precondition', 'request_id', 'request id ' .. req .. ' names a job being created from another scene')
    end
    return {'BUILD', old}
  end
end
if redis.call('EXISTS', jkey(jid)) == 1 then return refuse('internal', '', 'job id ' .. jid .. ' is taken') end
redis.call('HSET', jkey(jid), 'static', ARGV[5], 'state', JQUEUED, 'update', NOW_S, 'error', '', 'outputs', '',
  'ntasks', 0, 'pphases', '', 'prio', ARGV[6], 'held', 0, 'nrounds', 0,
  'building', 1, 'total', ARGV[7], 'digest', ARGV[8], 'req', req)
redis.call('ZADD', PENDING, NOW_S, jid)
if req ~= '' then redis.call('HSET', REQUESTS, req, jid) end
return {'BUILD', jid}
`)

// gone refuses to go on making a job that was deleted, or is being: it was abandoned (its
// maker gave up midway) and the purge took it.
var goneLib = `
local function gone(jid)
  local jk = jkey(jid)
  if redis.call('EXISTS', jk) == 1 and redis.call('HEXISTS', jk, 'doomed') == 0 then return nil end
  return refuse('gone', '', 'job ' .. jid .. ' is gone: its creation was abandoned and cleaned up; submit again')
end
`

// stageScript: ARGV[3] job id, [4] the staging's owner (the job id when creating it, the
// composite's "task@epoch" for a round), [5] that composite's task id (empty when
// creating), [6] its worker, [7] its epoch, [8] the first index of the chunk, [9...] its
// tasks: a count, then spec, phase, round and stage (store.Stage, computed by Go) of
// each. Chunks come in order from ntasks; what was written before (by a retry, or a
// second attempt of the same submission) is skipped. It answers {'STAGED'}, or {'NOOP'} if the
// composite's report was accepted already.
var stageScript = newScript(goneLib + `
local jid, owner, from = ARGV[3], ARGV[4], tonumber(ARGV[8])
local jk = jkey(jid)
local e = gone(jid)
if e then return e end
if ARGV[5] ~= '' then
  if repeated(ARGV[5], ARGV[6], ARGV[7]) then return {'NOOP'} end
  local e = held(ARGV[5], ARGV[6], ARGV[7])
  if e then return e end
end
local base = num(jk, 'ntasks')
local top = num(jk, 'stop')
if redis.call('HGET', jk, 'sowner') ~= owner then
  if from ~= base then return refuse('internal', '', 'job ' .. jid .. ': staging starts at task ' .. base .. ', not ' .. from) end
  redis.call('HSET', jk, 'sowner', owner, 'stop', base)
  top = base
end
local n = tonumber(ARGV[9])
if from + n <= top then return {'STAGED'} end
if from > top then return refuse('internal', '', 'job ' .. jid .. ': chunk at task ' .. from .. ' but the staged tasks end at ' .. top) end
for i = top - from, n - 1 do
  local a = 10 + 4 * i
  local idx = from + i
  redis.call('HSET', tkey(tid(jid, idx)), 'job', jid, 'idx', idx, 'spec', ARGV[a], 'phase', ARGV[a + 1], 'round', ARGV[a + 2],
    'stage', ARGV[a + 3], 'state', WAITING)
end
redis.call('HSET', jk, 'stop', from + n)
if redis.call('HEXISTS', jk, 'building') == 1 then redis.call('ZADD', PENDING, NOW_S, jid) end
return {'STAGED'}
`)

// publishScript: ARGV[3] job id, [4] its stages, [5] its phase counts, [6] its last round
// (see addtasks).
var publishScript = newScript(goneLib + `
local jid = ARGV[3]
local jk = jkey(jid)
local e = gone(jid)
if e then return e end
if redis.call('HEXISTS', jk, 'building') == 0 then return ok(0, 0, jid, nil) end
local total = num(jk, 'total')
if redis.call('HGET', jk, 'sowner') ~= jid or num(jk, 'stop') ~= total then
  return refuse('internal', '', 'job ' .. jid .. ' is published before its ' .. total .. ' tasks are staged')
end
local seq = redis.call('INCR', SEQ)
redis.call('HSET', jk, 'seq', seq)
redis.call('HDEL', jk, 'building', 'total', 'digest')
redis.call('ZREM', PENDING, jid)
redis.call('ZADD', JOBS, seq, jid)
addtasks(jid, 0, total, ARGV[4], ARGV[5], ARGV[6])
return ok(0, 0, jid, nil)
`)

// leaseScript: ARGV[3] worker, [4] lease expiry, [5...] phases. The job comes from the
// heads of the phases' ready sets (first: the best one that has not blocked the worker),
// the task is its lowest leasable index (see Stages).
var leaseScript = newScript(`
local worker, expire = ARGV[3], ARGV[4]

-- first returns the first member of ready set key, and its score, whose job has not
-- blocked worker, reading a page of members at a time.
local function first(key)
  local from = 0
  while true do
    local r = redis.call('ZRANGE', key, from, from + 15, 'WITHSCORES')
    if #r == 0 then return nil end
    for k = 1, #r, 2 do
      if redis.call('HEXISTS', jkey(jobof(r[k])), BLOCKED .. worker) == 0 then return r[k], tonumber(r[k + 1]) end
    end
    from = from + 16
  end
end

promote()
local best, score
for i = 5, #ARGV do
  local m, sc = first(readykey(ARGV[i]))
  if m and (not best or sc < score or (sc == score and m < best)) then best, score = m, sc end
end
if not best then return {'NONE'} end
local jid = jobof(best)
local jk = jkey(jid)
-- The lowest leasable index: a task put back is below the never-leased range.
local q = qkey(jid, redis.call('HGET', jk, 'cphase'))
local idx = redis.call('ZRANGE', q, 0, 0)[1]
if idx then
  redis.call('ZREM', q, idx)
else
  idx = redis.call('HINCRBY', jk, 'next', 1) - 1
end
local t = tid(jid, idx)
local k = tkey(t)
redis.call('HINCRBY', k, 'epoch', 1)
redis.call('HINCRBY', k, 'attempts', 1)
redis.call('HSET', k, 'state', LEASED, 'worker', worker, 'expire', expire, 'retry', '', 'progress', '0', 'ptime', NOW_S)
redis.call('ZADD', LEASES, expire, t)
redis.call('SADD', lkey(jid), t)
redis.call('HINCRBY', jk, 'held', 1)
place(jid)
local started = 0
if tonumber(redis.call('HGET', jk, 'state')) == JQUEUED then
  redis.call('HSET', jk, 'state', JRUNNING)
  started = 1
end
redis.call('HSET', jk, 'update', NOW_S)
return ok(started, 0, jid, t)
`)

// completeScript: ARGV[3] task, [4] worker, [5] epoch, [6] outputs. The last task of a
// stage opens the next one; the last of the job ends it with its stage's outputs.
var completeScript = newScript(`
local t, worker, epoch = ARGV[3], ARGV[4], ARGV[5]
if repeated(t, worker, epoch) then return again(t, epoch, ARGV[6]) end
local e = held(t, worker, epoch)
if e then return e end
local jid = succeed(t, ARGV[6])
local jk = jkey(jid)
if redis.call('HINCRBY', jk, 'left', -1) > 0 then return ok(0, 0, jid, t) end
local cur, nxt = num(jk, 'cur'), num(jk, 'curend')
if nxt < num(jk, 'ntasks') then
  openstage(jid, nxt)
  return ok(0, 1, jid, t)
end
local outs = {}
for i = cur, nxt - 1 do outs[#outs + 1] = redis.call('HGET', tkey(tid(jid, i)), 'outputs') end
succeedjob(jid, table.concat(outs))
return ok(1, 0, jid, t)
`)

// completeRoundScript: ARGV[3] task, [4] worker, [5] epoch, [6] outputs, [7] the round's
// report, [8] the final outputs, [14] the report's metrics (store.Metrics, kept with the
// task to compare a repeat with), [9] the number of the next round's tasks (0 ends the
// job), staged before by this lease (stageScript), [10] the stage of the first, [11] their
// stages, [12] phase counts and [13] round (see addtasks).
var completeRoundScript = newScript(`
local t, worker, epoch = ARGV[3], ARGV[4], ARGV[5]
if repeated(t, worker, epoch) then return again(t, epoch, ARGV[6], ARGV[14]) end
local e = held(t, worker, epoch)
if e then return e end
local h = redis.call('HMGET', tkey(t), 'job', 'idx', 'stage')
local jid, idx = h[1], tonumber(h[2])
local jk = jkey(jid)
if num(jk, 'cur') ~= idx or num(jk, 'ntasks') ~= idx + 1 then
  return refuse('internal', '', 'task ' .. t .. ' is not the last task of its round')
end
local n = tonumber(ARGV[9])
if n > 0 then
  if tonumber(ARGV[10]) <= tonumber(h[3]) then return refuse('internal', '', 'next round\'s task 0 is out of order') end
  if redis.call('HGET', jk, 'sowner') ~= t .. '@' .. epoch or num(jk, 'stop') ~= idx + 1 + n then
    return refuse('internal', '', 'the next round of job ' .. jid .. ' is not staged')
  end
end
succeed(t, ARGV[6])
redis.call('HSET', tkey(t), 'metrics', ARGV[14])
redis.call('RPUSH', rkey(jid), ARGV[7])
redis.call('HINCRBY', jk, 'nrounds', 1)
if n > 0 then
  addtasks(jid, idx + 1, idx + 1 + n, ARGV[11], ARGV[12], ARGV[13])
  return ok(0, 1, jid, t)
end
succeedjob(jid, ARGV[8])
return ok(1, 0, jid, t)
`)

// failScript: ARGV[3] task, [4] worker, [5] epoch, [6] message, [7] policy, [8] failure
// kind, [9] the job's error if the failure is permanent (store.PermanentFailure), else
// empty: a permanent failure fails the task and the job at once and blames no worker;
// [10] the attempt's log (a serialized pb.Artifact) or empty, which keeps the last one.
var failScript = newScript(`
local t, worker, epoch, kind = ARGV[3], ARGV[4], ARGV[5], ARGV[8]
local e = held(t, worker, epoch)
if e then return e end
if ARGV[10] ~= '' then redis.call('HSET', tkey(t), 'log', ARGV[10]) end
if ARGV[9] == '' then return fail(t, worker, ARGV[6], policy(ARGV[7]), kind) end
redis.call('HSET', tkey(t), 'error', ARGV[6], 'fkind', kind)
return failjob(t, redis.call('HGET', tkey(t), 'job'), ARGV[9])
`)

// failBlockedScript: ARGV[3] job id, [4] the job's error up to the latest block's reason
// (store.BlockedJobFailure with an empty reason), [5...] the workers. It fails the job if
// it has not ended and every one of the workers is blocked from it, else changes nothing.
var failBlockedScript = newScript(`
local jid = ARGV[3]
local jk = jkey(jid)
local e = unknown(jid)
if e then return e end
if ended(tonumber(redis.call('HGET', jk, 'state'))) or #ARGV < 5 then return {'NOOP'} end
for i = 5, #ARGV do
  if redis.call('HEXISTS', jk, BLOCKED .. ARGV[i]) == 0 then return {'NOOP'} end
end
-- The latest block, ordered as store.SortBlocked orders them: by time, then worker.
local lastAt, lastWorker, lastReason
local h = redis.call('HGETALL', jk)
for i = 1, #h, 2 do
  if string.sub(h[i], 1, #BLOCKED) == BLOCKED then
    local w = string.sub(h[i], #BLOCKED + 1)
    local at, reason = string.match(h[i + 1], '^(%d+) (.*)$')
    at = tonumber(at)
    if not lastAt or at > lastAt or (at == lastAt and w > lastWorker) then lastAt, lastWorker, lastReason = at, w, reason end
  end
end
endjob(jid, JFAILED, ARGV[4] .. lastReason, redis.call('HGET', jk, 'bkind'))
return ok(1, 0, jid, nil)
`)

// releaseScript: ARGV[3] task, [4] worker, [5] epoch.
var releaseScript = newScript(`
local t = ARGV[3]
local e = held(t, ARGV[4], ARGV[5])
if e then return e end
return ok(0, 1, requeue(t), t)
`)

// extendScript: ARGV[3] worker, [4] new expiry, [5] the stuck cutoff (µs: a lease whose
// progress last grew then or before is stuck), [6] the stuck message, [7] policy, [8] the
// phases exempt from the stuck check ("2,4"), [9...] task id, epoch and progress triples.
// It answers per triple 1 (extended), 0 (revoked) or, for a stuck lease (revoked and
// failed), fail's ok().
var extendScript = newScript(`
local worker, expire, cutoff = ARGV[3], ARGV[4], tonumber(ARGV[5])
local exempt = {}
for ph in string.gmatch(ARGV[8], '%d+') do exempt[ph] = true end
local out = {}
for i = 9, #ARGV, 3 do
  local t, progress = ARGV[i], ARGV[i + 2]
  local k = tkey(t)
  if held(t, worker, ARGV[i + 1]) then
    out[#out + 1] = 0
  else
    local h = redis.call('HMGET', k, 'progress', 'ptime', 'phase')
    local stuck = false
    if greater(progress, h[1] or '0') then
      redis.call('HSET', k, 'progress', progress, 'ptime', NOW_S)
    else
      stuck = not exempt[h[3]] and tonumber(h[2] or NOW_S) <= cutoff
    end
    if stuck then
      out[#out + 1] = fail(t, worker, ARGV[6], policy(ARGV[7]), FTRANSIENT)
    else
      redis.call('HSET', k, 'expire', expire)
      redis.call('ZADD', LEASES, expire, t)
      out[#out + 1] = 1
    end
  end
end
return out
`)

// expireScript: ARGV[3] MaxExpiries, [4] the expiry message, [5] the most leases to look
// at. It requeues each task whose lease expiry (its score in LEASES) is not after now,
// counting the expiry, or fails the task and its job at MaxExpiries; it answers the
// number of leases it looked at, then one ok() per task.
var expireScript = newScript(`
local expired = redis.call('ZRANGEBYSCORE', LEASES, '-inf', NOW_S, 'LIMIT', 0, tonumber(ARGV[5]))
local out = {#expired}
for _, t in ipairs(expired) do
  local k = tkey(t)
  -- An earlier failure in this loop may have ended the job, cancelling the lease.
  if tonumber(redis.call('HGET', k, 'state')) == LEASED then
    local n = redis.call('HINCRBY', k, 'expiries', 1)
    redis.call('HSET', k, 'error', ARGV[4], 'fkind', FTRANSIENT)
    if n >= tonumber(ARGV[3]) then
      out[#out + 1] = failjob(t, redis.call('HGET', k, 'job'), limitfailure(t, n))
    else
      out[#out + 1] = ok(0, 1, requeue(t), t)
    end
  end
end
return out
`)

// releaseWorkerScript: ARGV[3] worker. Live leases are few (a handful per worker), so it
// scans them rather than keeping a set per worker.
var releaseWorkerScript = newScript(`
local out = {}
for _, t in ipairs(redis.call('ZRANGE', LEASES, 0, -1)) do
  if redis.call('HGET', tkey(t), 'worker') == ARGV[3] then out[#out + 1] = ok(0, 1, requeue(t), t) end
end
return out
`)

// cancelScript: ARGV[3] job id.
var cancelScript = newScript(`
local jid = ARGV[3]
local e = live(jid)
if e then return e end
endjob(jid, JCANCELLED, '', 0)
return ok(1, 0, jid, nil)
`)

// priorityScript: ARGV[3] job id, [4] priority.
var priorityScript = newScript(`
local jid = ARGV[3]
local e = live(jid)
if e then return e end
redis.call('HSET', jkey(jid), 'prio', ARGV[4], 'update', NOW_S)
place(jid)
return ok(0, 0, jid, nil)
`)

// unblockScript: ARGV[3] job id, [4] worker (empty for all). It drops the worker's
// blocklist entry (b:) and failure count (f:); queued is 1 if a worker was unblocked.
var unblockScript = newScript(`
local jid, worker = ARGV[3], ARGV[4]
local jk = jkey(jid)
local e = unknown(jid)
if e then return e end
local drop, unblocked = {}, 0
if worker == '' then
  for _, f in ipairs(redis.call('HKEYS', jk)) do
    local blocked = string.sub(f, 1, #BLOCKED) == BLOCKED
    if blocked or string.sub(f, 1, #FAILURES) == FAILURES then drop[#drop + 1] = f end
    if blocked then unblocked = 1 end
  end
else
  drop = {BLOCKED .. worker, FAILURES .. worker}
  unblocked = redis.call('HEXISTS', jk, BLOCKED .. worker)
end
if #drop > 0 then redis.call('HDEL', jk, unpack(drop)) end
if unblocked == 1 then redis.call('HSET', jk, 'update', NOW_S) end
return ok(0, unblocked, jid, nil)
`)

// reopenScript: ARGV[3] job id, [4] a FAILED task of it to retry, or empty. It reopens a
// failed or cancelled job (store package comment, Reopening): endjob left the records of
// the current stage's tasks as they were, so the tasks leased since the stage opened,
// [cur, next), that did not succeed are written QUEUED and put in the queue (and out of
// DELAYED), while those never leased, [next, curend), and the later stages' are WAITING
// records already. Unlike the other scripts its work grows with a job's tasks (those of
// one stage at most), which an operator's requeue may cost. Refusals are worded as
// store.CheckReopen and store.CheckRetry word them.
var reopenScript = newScript(`
local jid, ft = ARGV[3], ARGV[4]
local jk = jkey(jid)
local e = unknown(jid)
if e then return e end
local j = redis.call('HMGET', jk, 'state', 'cur', 'next', 'curend', 'cphase')
local st, cur, nxt, curend, phase = tonumber(j[1]), tonumber(j[2]), tonumber(j[3]), tonumber(j[4]), j[5]
if ft ~= '' then
  local h = redis.call('HMGET', tkey(ft), 'job', 'state', 'idx')
  if h[1] ~= jid then return refuse('notfound', 'task_id', 'no task "' .. ft .. '"') end
  -- The state as a read shows it (codec.go, taskState).
  local ts, idx = tonumber(h[2]), tonumber(h[3])
  if ended(st) and (ts == WAITING or ts == QUEUED or ts == LEASED) then ts = CANCELLED end
  if ts == WAITING and cur <= idx and idx < curend then ts = QUEUED end
  if ts ~= FAILED then
    return refuse('precondition', '', 'task ' .. ft .. ' is TASK_STATE_' .. TASK_STATES[ts] .. ', not failed: only a failed task can be retried')
  end
end
if st == JSUCCEEDED then
  return refuse('precondition', '', 'job ' .. jid .. ' succeeded: only a failed or cancelled job can be requeued')
end
if not ended(st) then
  return refuse('precondition', '', 'job ' .. jid .. ' has not ended (JOB_STATE_' .. JOB_STATES[st] ..
    '): only a failed or cancelled job can be requeued')
end
for i = cur, nxt - 1 do
  local t = tid(jid, i)
  local k = tkey(t)
  if tonumber(redis.call('HGET', k, 'state')) ~= SUCCEEDED then
    redis.call('HSET', k, 'state', QUEUED, 'worker', '', 'retry', '', 'failures', 0, 'expiries', 0)
    redis.call('ZREM', DELAYED, t)
    redis.call('ZADD', qkey(jid, phase), i, tostring(i))
  end
end
redis.call('HSET', jk, 'state', JQUEUED, 'error', '', 'fkind', 0, 'update', NOW_S)
redis.call('HDEL', jk, 'end')
redis.call('ZREM', ENDED, jid)
place(jid)
if ft == '' then ft = nil end
return ok(1, 1, jid, ft)
`)

// deleteScript: ARGV[3] job id. It cancels the job if it has not ended and dooms it (see
// purgeScript).
var deleteScript = newScript(`
local jid = ARGV[3]
local e = unknown(jid)
if e then return e end
local changed = 0
if not ended(tonumber(redis.call('HGET', jkey(jid), 'state'))) then
  endjob(jid, JCANCELLED, '', 0)
  changed = 1
end
doom(jid)
return ok(changed, 0, jid, nil)
`)

// purgeScript: ARGV[3] ended-before (µs), [4] abandoned-before (µs), [5] budget. It marks
// for deletion (doomed: no read sees the job from then on, its request id is forgotten)
// up to 16 jobs that ended before ARGV[3] and 16 half-made jobs not grown since ARGV[4],
// then deletes the records of the doomed jobs, a batch of task records at a time, from
// their last task down, at most budget keys in all: a job of 105,539 tasks takes many
// calls, each about a millisecond. It answers {1 if work is left, the ids of the jobs
// finished}.
var purgeScript = newScript(`
local budget = tonumber(ARGV[5])
for _, jid in ipairs(redis.call('ZRANGEBYSCORE', ENDED, '-inf', '(' .. ARGV[3], 'LIMIT', 0, 16)) do doom(jid) end
for _, jid in ipairs(redis.call('ZRANGEBYSCORE', PENDING, '-inf', '(' .. ARGV[4], 'LIMIT', 0, 16)) do doom(jid) end
local out = {0}
for _, jid in ipairs(redis.call('ZRANGE', DOOMED, 0, 15)) do
  if budget <= 0 then out[1] = 1 break end
  local jk = jkey(jid)
  local top = num(jk, 'doomed')
  while top > 0 and budget > 0 do
    local keys = {}
    for i = top - 1, math.max(top - 256, 0, top - budget), -1 do keys[#keys + 1] = tkey(tid(jid, i)) end
    redis.call('DEL', unpack(keys))
    top, budget = top - #keys, budget - #keys
  end
  if top > 0 then
    redis.call('HSET', jk, 'doomed', top)
    out[1] = 1
  else
    redis.call('DEL', jk, rkey(jid), skey(jid), lkey(jid), qkey(jid, redis.call('HGET', jk, 'cphase') or '0'))
    redis.call('ZREM', DOOMED, jid)
    out[#out + 1] = jid
    budget = budget - 1
  end
end
if redis.call('ZCARD', DOOMED) > 0 or redis.call('ZCOUNT', ENDED, '-inf', '(' .. ARGV[3]) > 0 or
  redis.call('ZCOUNT', PENDING, '-inf', '(' .. ARGV[4]) > 0 then out[1] = 1 end
return out
`)

// scripts are every script, loaded into Redis when a Store opens.
var scripts []*redis.Script

// newScript makes a script of body run as one operation (see Operations).
func newScript(body string) *redis.Script {
	sc := redis.NewScript(preamble + lib + "local function main()\n" + body + `
end
local done = redis.call('GET', KEYS[2])
local r
if done then
  r = cmsgpack.unpack(done)
else
  r = main()
  redis.call('SET', KEYS[2], cmsgpack.pack(r), 'PX', ` + strconv.FormatInt(OpTTL.Milliseconds(), 10) + `)
end
return render(r)
`)
	scripts = append(scripts, sc)
	return sc
}
