package redisstore

// Key layout under the prefix (the Lua library in scripts.go builds the same names):
//
//	seq                   INCR counter: job creation sequence
//	jobs                  zset job id, score = sequence: ListJobs paging, newest first
//	req                   hash request id -> job id: CreateJob deduplication
//	j:{job}               hash: the job record (see codec.go) and its counters
//	r:{job}               list: the job's RoundReports (binary protobuf)
//	s:{job}               hash: first task index of a stage -> index after its last
//	t:{job}.{index}       hash: one task record (see codec.go)
//	q:{job}:{phase}       zset task index, score = index: the job's leasable tasks
//	ready:{phase}         zset "{seq, 16 digits}:{job}", score = (1000 - priority)·2^32 +
//	                      leases held: jobs with leasable tasks of phase (scripts.go)
//	leases                zset task id, score = lease expiry (µs): live leases
//	delayed               zset task id, score = retry time (µs): queued tasks in backoff

func (s *Store) key(name string) string { return s.prefix + name }

func (s *Store) jobKey(jobID string) string    { return s.prefix + "j:" + jobID }
func (s *Store) roundsKey(jobID string) string { return s.prefix + "r:" + jobID }
func (s *Store) taskKey(taskID string) string  { return s.prefix + "t:" + taskID }
