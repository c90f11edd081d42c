package redisstore

import "github.com/redis/go-redis/v9"

// Every script gets ARGV[1] = the key prefix and ARGV[2] = now (Unix microseconds, from
// Options.Clock), then its own arguments. KEYS[1] is the prefix's "jobs" key and only
// routes the call; the scripts build the other keys from the prefix (see keys.go for
// the layout, which this library must match).
//
// Times and epochs are stored as the strings Go sent and compared with tonumber:
// microseconds since 1970 stay below 2^53, so the comparison is exact, while Lua would
// print such a number with only 14 digits.
//
// Scripts that change a task or a job answer through ok(): {"OK", jobStateChanged,
// queued, HGETALL job, LRANGE rounds, HGETALL task}; a refusal is {"E", kind, field,
// message}; a repeated report is {"NOOP"}.
const lib = `
local P = ARGV[1]
local NOW_S = ARGV[2]
local NOW = tonumber(NOW_S)
local WAITING, QUEUED, LEASED, SUCCEEDED, FAILED, CANCELLED = 1, 2, 3, 4, 5, 6
local TASK_STATES = {'WAITING', 'QUEUED', 'LEASED', 'SUCCEEDED', 'FAILED', 'CANCELLED'}
local JQUEUED, JRUNNING, JSUCCEEDED, JFAILED, JCANCELLED = 1, 2, 3, 4, 5
local JOB_STATES = {'QUEUED', 'RUNNING', 'SUCCEEDED', 'FAILED', 'CANCELLED'}
local LEASES = P .. 'leases'

local function jkey(jid) return P .. 'j:' .. jid end
local function rkey(jid) return P .. 'r:' .. jid end
local function skey(jid) return P .. 's:' .. jid end
local function tkey(t) return P .. 't:' .. t end
local function qkey(jid, phase) return P .. 'q:' .. jid .. ':' .. phase end
local function readykey(phase) return P .. 'ready:' .. phase end
local function tid(jid, i) return jid .. '.' .. i end
local function num(key, field) return tonumber(redis.call('HGET', key, field) or '0') end

local function refuse(kind, field, msg) return {'E', kind, field, msg} end

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
  redis.call('ZADD', readykey(phase), redis.call('HGET', jk, 'seq'), jid)
  redis.call('HSET', jk, 'cur', start, 'curend', stop, 'left', stop - start)
end

-- append adds the tasks described from ARGV[a] on (a count, then spec, phase, round per
-- task) after the job's last task, records their stages and the progress of the latest
-- round, and queues their first stage.
local function append(jid, a)
  local jk = jkey(jid)
  local n = tonumber(ARGV[a])
  local base = num(jk, 'ntasks')
  local R = ARGV[a + 3 * n]
  if redis.call('HGET', jk, 'pround') ~= R then
    for ph in string.gmatch(redis.call('HGET', jk, 'pphases') or '', '%d+') do
      redis.call('HDEL', jk, 'pt:' .. ph, 'ps:' .. ph)
    end
    redis.call('HSET', jk, 'pround', R, 'pphases', '')
  end
  local plist = redis.call('HGET', jk, 'pphases')
  local stage, stageStart
  for i = 0, n - 1 do
    local spec, phase, round = ARGV[a + 1 + 3 * i], ARGV[a + 2 + 3 * i], ARGV[a + 3 + 3 * i]
    local idx = base + i
    redis.call('HSET', tkey(tid(jid, idx)), 'job', jid, 'idx', idx, 'spec', spec, 'phase', phase, 'round', round,
      'state', WAITING, 'epoch', 0, 'attempts', 0, 'failures', 0, 'worker', '', 'error', '', 'outputs', '', 'expire', 0)
    local st = math.max(tonumber(round), 1) * 256 + tonumber(phase)
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

-- requeue puts a leased task back in its job's queue; it returns the job id.
local function requeue(t)
  local k = tkey(t)
  local h = redis.call('HMGET', k, 'job', 'idx', 'phase')
  local jk = jkey(h[1])
  redis.call('HSET', k, 'state', QUEUED, 'worker', '')
  redis.call('ZADD', qkey(h[1], h[3]), h[2], h[2])
  redis.call('ZADD', readykey(h[3]), redis.call('HGET', jk, 'seq'), h[1])
  redis.call('ZREM', LEASES, t)
  redis.call('HSET', jk, 'update', NOW_S)
  return h[1]
end

-- succeed records a task's success and its round's progress; it returns the job id.
local function succeed(t, outputs)
  local k = tkey(t)
  redis.call('HSET', k, 'state', SUCCEEDED, 'outputs', outputs)
  redis.call('ZREM', LEASES, t)
  local h = redis.call('HMGET', k, 'job', 'round', 'phase')
  local jk = jkey(h[1])
  redis.call('HSET', jk, 'update', NOW_S)
  if redis.call('HGET', jk, 'pround') == h[2] then redis.call('HINCRBY', jk, 'ps:' .. h[3], 1) end
  return h[1]
end

local function succeedjob(jid, outputs)
  redis.call('HSET', jkey(jid), 'state', JSUCCEEDED, 'end', NOW_S, 'outputs', outputs)
end

-- endjob moves a job to a terminal state, empties its queue and cancels its unfinished
-- tasks. Only the current stage and those after it can be unfinished.
local function endjob(jid, state, msg)
  local jk = jkey(jid)
  redis.call('HSET', jk, 'state', state, 'error', msg, 'end', NOW_S, 'update', NOW_S)
  local cur, n = num(jk, 'cur'), num(jk, 'ntasks')
  local phase = redis.call('HGET', tkey(tid(jid, cur)), 'phase')
  redis.call('DEL', qkey(jid, phase))
  redis.call('ZREM', readykey(phase), jid)
  for i = cur, n - 1 do
    local t = tid(jid, i)
    local st = tonumber(redis.call('HGET', tkey(t), 'state'))
    if st == WAITING or st == QUEUED or st == LEASED then
      redis.call('HSET', tkey(t), 'state', CANCELLED)
      redis.call('ZREM', LEASES, t)
    end
  end
end
`

// createScript: ARGV[3] job id, [4] request id, [5] the job's static record, [6...] the
// tasks (see append). A request id seen before answers with the job it created.
var createScript = newScript(`
local jid, req = ARGV[3], ARGV[4]
if req ~= '' then
  local old = redis.call('HGET', P .. 'req', req)
  if old then return ok(0, 0, old, nil) end
end
if redis.call('EXISTS', jkey(jid)) == 1 then return refuse('internal', '', 'job id ' .. jid .. ' is taken') end
local seq = redis.call('INCR', P .. 'seq')
redis.call('HSET', jkey(jid), 'static', ARGV[5], 'seq', seq, 'state', JQUEUED, 'update', NOW_S,
  'error', '', 'outputs', '', 'ntasks', 0, 'pphases', '')
redis.call('ZADD', P .. 'jobs', seq, jid)
if req ~= '' then redis.call('HSET', P .. 'req', req, jid) end
append(jid, 6)
return ok(0, 0, jid, nil)
`)

// leaseScript: ARGV[3] worker, [4] lease expiry, [5...] phases. The oldest job with a
// queued task of one of the phases comes from the per-phase ready sets (score = job
// sequence), its lowest queued index from the job's per-phase queues.
var leaseScript = newScript(`
local worker, expire = ARGV[3], ARGV[4]
local jid, seq
for i = 5, #ARGV do
  local r = redis.call('ZRANGE', readykey(ARGV[i]), 0, 0, 'WITHSCORES')
  if r[1] and (not seq or tonumber(r[2]) < seq) then jid, seq = r[1], tonumber(r[2]) end
end
if not jid then return {'NONE'} end
local idx, member, phase
for i = 5, #ARGV do
  local r = redis.call('ZRANGE', qkey(jid, ARGV[i]), 0, 0, 'WITHSCORES')
  if r[1] and (not idx or tonumber(r[2]) < idx) then idx, member, phase = tonumber(r[2]), r[1], ARGV[i] end
end
local q = qkey(jid, phase)
redis.call('ZREM', q, member)
if redis.call('ZCARD', q) == 0 then redis.call('ZREM', readykey(phase), jid) end
local t = tid(jid, member)
local k = tkey(t)
redis.call('HINCRBY', k, 'epoch', 1)
redis.call('HINCRBY', k, 'attempts', 1)
redis.call('HSET', k, 'state', LEASED, 'worker', worker, 'expire', expire)
redis.call('ZADD', LEASES, expire, t)
local jk = jkey(jid)
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
local h = redis.call('HMGET', tkey(t), 'job', 'idx', 'phase', 'round')
local jid, idx = h[1], tonumber(h[2])
local jk = jkey(jid)
if num(jk, 'cur') ~= idx or num(jk, 'ntasks') ~= idx + 1 then
  return refuse('internal', '', 'task ' .. t .. ' is not the last task of its round')
end
local n = tonumber(ARGV[9])
if n > 0 and math.max(tonumber(ARGV[12]), 1) * 256 + tonumber(ARGV[11]) <= math.max(tonumber(h[4]), 1) * 256 + tonumber(h[3]) then
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

// failScript: ARGV[3] task, [4] worker, [5] epoch, [6] message, [7] MaxAttempts.
var failScript = newScript(`
local t, worker, epoch, msg = ARGV[3], ARGV[4], ARGV[5], ARGV[6]
local e = held(t, worker, epoch)
if e then return e end
local k = tkey(t)
local failures = redis.call('HINCRBY', k, 'failures', 1)
redis.call('HSET', k, 'error', msg)
if failures < tonumber(ARGV[7]) then return ok(0, 1, requeue(t), t) end
redis.call('HSET', k, 'state', FAILED)
redis.call('ZREM', LEASES, t)
local jid = redis.call('HGET', k, 'job')
endjob(jid, JFAILED, 'task ' .. t .. ' failed ' .. failures .. ' times; last error: ' .. msg)
return ok(1, 0, jid, t)
`)

// releaseScript: ARGV[3] task, [4] worker, [5] epoch.
var releaseScript = newScript(`
local t = ARGV[3]
local e = held(t, ARGV[4], ARGV[5])
if e then return e end
return ok(0, 1, requeue(t), t)
`)

// extendScript: ARGV[3] worker, [4] new expiry, [5...] task id and epoch pairs. It
// answers 1 (extended) or 0 (revoked) per pair.
var extendScript = newScript(`
local worker, expire = ARGV[3], ARGV[4]
local out = {}
for i = 5, #ARGV, 2 do
  local t = ARGV[i]
  if held(t, worker, ARGV[i + 1]) then
    out[#out + 1] = 0
  else
    redis.call('HSET', tkey(t), 'expire', expire)
    redis.call('ZADD', LEASES, expire, t)
    out[#out + 1] = 1
  end
end
return out
`)

// expireScript requeues every task whose lease expiry (its score in LEASES) is not
// after now; it answers one ok() per task.
var expireScript = newScript(`
local out = {}
for _, t in ipairs(redis.call('ZRANGEBYSCORE', LEASES, '-inf', NOW_S)) do
  out[#out + 1] = ok(0, 1, requeue(t), t)
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
local st = redis.call('HGET', jkey(jid), 'state')
if not st then return refuse('notfound', 'job_id', 'no job "' .. jid .. '"') end
st = tonumber(st)
if st == JSUCCEEDED or st == JFAILED or st == JCANCELLED then
  return refuse('precondition', '', 'job ' .. jid .. ' has already ended (JOB_STATE_' .. JOB_STATES[st] .. ')')
end
endjob(jid, JCANCELLED, '')
return ok(1, 0, jid, nil)
`)

func newScript(body string) *redis.Script { return redis.NewScript(lib + body) }
