package redisstore

import "github.com/redis/go-redis/v9"

// Every script gets ARGV[1] = the key prefix and ARGV[2] = now (Unix microseconds, from
// Options.Clock), then its own arguments. KEYS[1] is the prefix's "jobs" key and only
// routes the call; the scripts build the other keys from the prefix with the functions
// the preamble (preamble.go) declares from keys.go, and name task and job states by the
// preamble's locals (WAITING ... CANCELLED, JQUEUED ... JCANCELLED).
//
// Times and epochs are stored as the strings Go sent and compared with tonumber:
// microseconds since 1970 stay below 2^53, so the comparison is exact, while Lua would
// print such a number with only 14 digits.
//
// Scripts that change a task or a job answer through ok(): {"OK", jobStateChanged,
// queued, HGETALL job, LRANGE rounds, HGETALL task}; a refusal is {"E", kind, field,
// message}; a repeated report is {"NOOP"}.
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
// ones back (promote).
const lib = `
local function tid(jid, i) return jid .. '.' .. i end
local function num(key, field) return tonumber(redis.call('HGET', key, field) or '0') end

local function refuse(kind, field, msg) return {'E', kind, field, msg} end

-- live refuses a job that does not exist or has ended.
local function live(jid)
  local st = redis.call('HGET', jkey(jid), 'state')
  if not st then return refuse('notfound', 'job_id', 'no job "' .. jid .. '"') end
  st = tonumber(st)
  if st == JSUCCEEDED or st == JFAILED or st == JCANCELLED then
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
-- and leases held, or takes it out when that phase has no leasable task.
local function place(jid)
  local jk = jkey(jid)
  local h = redis.call('HMGET', jk, 'seq', 'prio', 'held', 'cur')
  local phase = redis.call('HGET', tkey(tid(jid, h[4] or '0')), 'phase')
  local member = string.rep('0', 16 - #h[1]) .. h[1] .. ':' .. jid
  if redis.call('EXISTS', qkey(jid, phase)) == 1 then
    redis.call('ZADD', readykey(phase), (1000 - tonumber(h[2] or '0')) * 4294967296 + tonumber(h[3] or '0'), member)
  else
    redis.call('ZREM', readykey(phase), member)
  end
end

-- unlease ends t's lease: it leaves LEASES and its job holds one lease less.
local function unlease(t, jid)
  redis.call('ZREM', LEASES, t)
  redis.call('HINCRBY', jkey(jid), 'held', -1)
end

local function ok(changed, queued, jid, t)
  local task = {}
  if t then task = redis.call('HGETALL', tkey(t)) end
  return {'OK', changed, queued, redis.call('HGETALL', jkey(jid)), redis.call('LRANGE', rkey(jid), 0, -1), task}
end

-- held refuses a report unless (worker, epoch) holds t's live lease.
local function held(t, worker, epoch)
  local h = redis.call('HMGET', tkey(t), 'epoch', 'worker', 'state', 'expire')
  if not h[3] then return refuse('notfound', 'task_id', 'no task "' .. t .. '"') end
  local pre = 'task ' .. t .. ': lease epoch ' .. epoch
  if h[1] ~= epoch then return refuse('precondition', '', pre .. ' is retired (current epoch ' .. h[1] .. ')') end
  if h[2] ~= worker then return refuse('precondition', '', pre .. ' is held by another worker, not ' .. worker) end
  local st = tonumber(h[3])
  if st ~= LEASED then return refuse('precondition', '', pre .. ' is no longer held (task is TASK_STATE_' .. TASK_STATES[st] .. ')') end
  if NOW >= tonumber(h[4]) then return refuse('precondition', '', pre .. ' expired') end
  return nil
end

-- repeated: t already succeeded under this very lease, so the report was accepted before.
local function repeated(t, worker, epoch)
  local h = redis.call('HMGET', tkey(t), 'state', 'epoch', 'worker')
  return tonumber(h[1]) == SUCCEEDED and h[2] == epoch and h[3] == worker
end

-- openstage queues the stage starting at task index start and makes it the current one.
local function openstage(jid, start)
  local jk = jkey(jid)
  local stop = tonumber(redis.call('HGET', skey(jid), start))
  local phase = redis.call('HGET', tkey(tid(jid, start)), 'phase')
  local q = qkey(jid, phase)
  for i = start, stop - 1 do
    redis.call('HSET', tkey(tid(jid, i)), 'state', QUEUED)
    redis.call('ZADD', q, i, i)
  end
  redis.call('HSET', jk, 'cur', start, 'curend', stop, 'left', stop - start)
  place(jid)
end

-- append adds the tasks described from ARGV[a] on (a count, then spec, phase, round and
-- stage per task: store.Stage, computed by Go) after the job's last task, records their
-- stages and the progress of the latest round, and queues their first stage.
local function append(jid, a)
  local jk = jkey(jid)
  local n = tonumber(ARGV[a])
  local base = num(jk, 'ntasks')
  local R = ARGV[a + 4 * n - 1]
  if redis.call('HGET', jk, 'pround') ~= R then
    for ph in string.gmatch(redis.call('HGET', jk, 'pphases') or '', '%d+') do
      redis.call('HDEL', jk, 'pt:' .. ph, 'ps:' .. ph)
    end
    redis.call('HSET', jk, 'pround', R, 'pphases', '')
  end
  local plist = redis.call('HGET', jk, 'pphases')
  local stage, stageStart
  for i = 0, n - 1 do
    local spec, phase, round, st = ARGV[a + 1 + 4 * i], ARGV[a + 2 + 4 * i], ARGV[a + 3 + 4 * i], ARGV[a + 4 + 4 * i]
    local idx = base + i
    redis.call('HSET', tkey(tid(jid, idx)), 'job', jid, 'idx', idx, 'spec', spec, 'phase', phase, 'round', round,
      'stage', st, 'state', WAITING, 'epoch', 0, 'attempts', 0, 'failures', 0, 'expiries', 0, 'worker', '', 'error', '',
      'outputs', '', 'expire', 0, 'retry', '', 'progress', '0', 'ptime', 0)
    if st ~= stage then
      if stage then redis.call('HSET', skey(jid), stageStart, idx) end
      stage, stageStart = st, idx
    end
    if round == R then
      if redis.call('HEXISTS', jk, 'pt:' .. phase) == 0 then
        if plist == '' then plist = phase else plist = plist .. ',' .. phase end
      end
      redis.call('HINCRBY', jk, 'pt:' .. phase, 1)
    end
  end
  redis.call('HSET', skey(jid), stageStart, base + n)
  redis.call('HSET', jk, 'ntasks', base + n, 'pphases', plist)
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

-- promote queues the delayed tasks whose backoff has ended.
local function promote()
  for _, t in ipairs(redis.call('ZRANGEBYSCORE', DELAYED, '-inf', NOW_S)) do
    redis.call('ZREM', DELAYED, t)
    local h = redis.call('HMGET', tkey(t), 'job', 'idx', 'phase')
    redis.call('ZADD', qkey(h[1], h[3]), h[2], h[2])
    place(h[1])
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
end

-- endjob moves a job to a terminal state (with why and the failure kind for JFAILED),
-- empties its queue and cancels its unfinished tasks. Only the current stage and those
-- after it can be unfinished.
local function endjob(jid, state, msg, kind)
  local jk = jkey(jid)
  redis.call('HSET', jk, 'state', state, 'error', msg, 'fkind', kind, 'end', NOW_S, 'update', NOW_S, 'held', 0)
  local cur, n = num(jk, 'cur'), num(jk, 'ntasks')
  redis.call('DEL', qkey(jid, redis.call('HGET', tkey(tid(jid, cur)), 'phase')))
  place(jid)
  for i = cur, n - 1 do
    local t = tid(jid, i)
    local st = tonumber(redis.call('HGET', tkey(t), 'state'))
    if st == WAITING or st == QUEUED or st == LEASED then
      redis.call('HSET', tkey(t), 'state', CANCELLED)
      redis.call('ZREM', LEASES, t)
      redis.call('ZREM', DELAYED, t)
    end
  end
end

-- failjob fails leased task t and its job with msg, of the kind of t's last failure.
local function failjob(t, jid, msg)
  local k = tkey(t)
  redis.call('HSET', k, 'state', FAILED)
  redis.call('ZREM', LEASES, t)
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

// createScript: ARGV[3] job id, [4] request id, [5] the job's static record, [6] its
// priority, [7...] the tasks (see append). A request id seen before answers with the job
// it created.
var createScript = newScript(`
local jid, req = ARGV[3], ARGV[4]
if req ~= '' then
  local old = redis.call('HGET', REQUESTS, req)
  if old then return ok(0, 0, old, nil) end
end
if redis.call('EXISTS', jkey(jid)) == 1 then return refuse('internal', '', 'job id ' .. jid .. ' is taken') end
local seq = redis.call('INCR', SEQ)
redis.call('HSET', jkey(jid), 'static', ARGV[5], 'seq', seq, 'state', JQUEUED, 'update', NOW_S,
  'error', '', 'outputs', '', 'ntasks', 0, 'pphases', '', 'prio', ARGV[6], 'held', 0)
redis.call('ZADD', JOBS, seq, jid)
if req ~= '' then redis.call('HSET', REQUESTS, req, jid) end
append(jid, 7)
return ok(0, 0, jid, nil)
`)

// leaseScript: ARGV[3] worker, [4] lease expiry, [5...] phases. The job comes from the
// heads of the phases' ready sets (first: the best one that has not blocked the worker),
// the task is its lowest queued index in the job's per-phase queues.
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
local idx, member, phase
for i = 5, #ARGV do
  local r = redis.call('ZRANGE', qkey(jid, ARGV[i]), 0, 0, 'WITHSCORES')
  if r[1] and (not idx or tonumber(r[2]) < idx) then idx, member, phase = tonumber(r[2]), r[1], ARGV[i] end
end
redis.call('ZREM', qkey(jid, phase), member)
local t = tid(jid, member)
local k = tkey(t)
redis.call('HINCRBY', k, 'epoch', 1)
redis.call('HINCRBY', k, 'attempts', 1)
redis.call('HSET', k, 'state', LEASED, 'worker', worker, 'expire', expire, 'retry', '', 'progress', '0', 'ptime', NOW_S)
redis.call('ZADD', LEASES, expire, t)
local jk = jkey(jid)
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
if repeated(t, worker, epoch) then return {'NOOP'} end
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
// report, [8] the final outputs, [9...] the next round's tasks (see append; count 0 ends
// the job).
var completeRoundScript = newScript(`
local t, worker, epoch = ARGV[3], ARGV[4], ARGV[5]
if repeated(t, worker, epoch) then return {'NOOP'} end
local e = held(t, worker, epoch)
if e then return e end
local h = redis.call('HMGET', tkey(t), 'job', 'idx', 'stage')
local jid, idx = h[1], tonumber(h[2])
local jk = jkey(jid)
if num(jk, 'cur') ~= idx or num(jk, 'ntasks') ~= idx + 1 then
  return refuse('internal', '', 'task ' .. t .. ' is not the last task of its round')
end
local n = tonumber(ARGV[9])
if n > 0 and tonumber(ARGV[13]) <= tonumber(h[3]) then
  return refuse('internal', '', 'next round\'s task 0 is out of order')
end
succeed(t, ARGV[6])
redis.call('RPUSH', rkey(jid), ARGV[7])
if n > 0 then
  append(jid, 9)
  return ok(0, 1, jid, t)
end
succeedjob(jid, ARGV[8])
return ok(1, 0, jid, t)
`)

// failScript: ARGV[3] task, [4] worker, [5] epoch, [6] message, [7] policy, [8] failure
// kind, [9] the job's error if the failure is permanent (store.PermanentFailure), else
// empty: a permanent failure fails the task and the job at once and blames no worker.
var failScript = newScript(`
local t, worker, epoch, kind = ARGV[3], ARGV[4], ARGV[5], ARGV[8]
local e = held(t, worker, epoch)
if e then return e end
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
local st = redis.call('HGET', jk, 'state')
if not st then return refuse('notfound', 'job_id', 'no job "' .. jid .. '"') end
st = tonumber(st)
if st == JSUCCEEDED or st == JFAILED or st == JCANCELLED or #ARGV < 5 then return {'NOOP'} end
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

// expireScript: ARGV[3] MaxExpiries, [4] the expiry message. It requeues every task whose
// lease expiry (its score in LEASES) is not after now, counting the expiry, or fails the
// task and its job at MaxExpiries; it answers one ok() per task.
var expireScript = newScript(`
local out = {}
for _, t in ipairs(redis.call('ZRANGEBYSCORE', LEASES, '-inf', NOW_S)) do
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
if redis.call('EXISTS', jk) == 0 then return refuse('notfound', 'job_id', 'no job "' .. jid .. '"') end
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

func newScript(body string) *redis.Script { return redis.NewScript(preamble + lib + body) }
