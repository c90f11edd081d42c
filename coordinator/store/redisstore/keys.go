package redisstore

// Key layout under the prefix. These names are the only place keys are spelled: the Go
// methods below and the Lua library (the preamble, preamble.go) are both built from them.
//
//	layout                string: the key layout's version (redisstore.go, layoutVersion)
//	seq                   INCR counter: job creation sequence
//	jobs                  zset job id, score = sequence: ListJobs paging, newest first
//	req                   hash request id -> job id: CreateJob deduplication
//	pending               zset job id, score = when it last grew (µs): jobs being created
//	ended                 zset job id, score = end time (µs): ended jobs, for the purge
//	doomed                zset job id: jobs being deleted (purgeScript)
//	j:{job}               hash: the job record (see codec.go) and its counters
//	r:{job}               list: the job's RoundReports (binary protobuf)
//	s:{job}               hash: first task index of a stage -> index after its last
//	l:{job}               set of task ids: the job's live leases (cancelled with the job)
//	t:{job}.{index}       hash: one task record (see codec.go)
//	q:{job}:{phase}       zset task index, score = index: the current stage's tasks put
//	                      back in the queue (those never leased are a range: scripts.go)
//	ready:{phase}         zset "{seq, 16 digits}:{job}", score = (1000 - priority)·2^32 +
//	                      leases held: jobs with leasable tasks of phase (scripts.go)
//	leases                zset task id, score = lease expiry (µs): live leases
//	delayed               zset task id, score = retry time (µs): queued tasks in backoff
//	workers               zset worker id, score = registration sequence: ListWorkers
//	seen                  zset worker id, score = when last heard from (µs)
//	holders               hash task id -> the worker holding its latest lease
//	wseq                  INCR counter: worker registration sequence
//	w:{worker}            hash: one registered worker (workers.go)
//	op:{origin}.{token}   string, expires: an operation's answer (scripts.go, Operations);
//	                      origin names the Store value that ran it (feed.go)
//	changes               stream, trimmed to about FeedLength entries: every change as
//	                      the scripts answer it, for the other replicas (feed.go)
const (
	layoutKey   = "layout"
	seqKey      = "seq"
	jobsKey     = "jobs"
	requestsKey = "req"
	leasesKey   = "leases"
	delayedKey  = "delayed"
	pendingKey  = "pending"
	endedKey    = "ended"
	doomedKey   = "doomed"
	opPrefix    = "op:"
	changesKey  = "changes"
	workersKey  = "workers"
	seenKey     = "seen"
	holdersKey  = "holders"
	wseqKey     = "wseq"

	jobPrefix    = "j:"
	workerPrefix = "w:"
	roundsPrefix = "r:"
	stagesPrefix = "s:"
	leasesPrefix = "l:"
	taskPrefix   = "t:"
	queuePrefix  = "q:"
	readyPrefix  = "ready:"
	// queueSeparator stands between the job and the phase in a queue key.
	queueSeparator = ":"

	// Field prefixes of a job record (codec.go): a blocked worker, a worker's failures.
	blockedField  = "b:"
	failuresField = "f:"
)

func (s *Store) key(name string) string { return s.prefix + name }

func (s *Store) jobKey(jobID string) string    { return s.prefix + jobPrefix + jobID }
func (s *Store) roundsKey(jobID string) string { return s.prefix + roundsPrefix + jobID }
func (s *Store) taskKey(taskID string) string  { return s.prefix + taskPrefix + taskID }
