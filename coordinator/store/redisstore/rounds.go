package redisstore

import (
	"context"
	"fmt"
	"slices"
	"sync"

	"github.com/redis/go-redis/v9"
	"google.golang.org/protobuf/proto"

	"photonfarm/coordinator/errs"
	pb "photonfarm/proto/renderfarm/v1"
)

// A progressive job's round reports are part of every pb.Job the store returns, but they
// never change once recorded: the job record counts them (nrounds) and the scripts answer
// with the record alone, and the reports are read from the list r:{job} once each and kept
// here, decoded. So a change's cost does not grow with the rounds before it (the jobs the
// store returns share the cached reports, which nobody may change).

// maxCachedRounds bounds the reports kept; past it whole jobs are forgotten (and read
// again if they come back).
const maxCachedRounds = 1 << 16

type roundCache struct {
	mu    sync.Mutex
	jobs  map[string][]*pb.RoundReport
	total int
}

func (c *roundCache) get(jobID string) []*pb.RoundReport {
	c.mu.Lock()
	defer c.mu.Unlock()
	return c.jobs[jobID]
}

// put remembers a job's reports if they are more than those remembered.
func (c *roundCache) put(jobID string, rs []*pb.RoundReport) {
	c.mu.Lock()
	defer c.mu.Unlock()
	if c.jobs == nil {
		c.jobs = make(map[string][]*pb.RoundReport)
	}
	old := c.jobs[jobID]
	if len(old) >= len(rs) {
		return
	}
	for id, r := range c.jobs {
		if c.total+len(rs)-len(old) <= maxCachedRounds {
			break
		}
		if id != jobID {
			c.total -= len(r)
			delete(c.jobs, id)
		}
	}
	c.total += len(rs) - len(old)
	c.jobs[jobID] = rs
}

// forget drops a deleted job's reports.
func (c *roundCache) forget(jobID string) {
	c.mu.Lock()
	defer c.mu.Unlock()
	c.total -= len(c.jobs[jobID])
	delete(c.jobs, jobID)
}

// decodeJobs rebuilds jobs from their records, with their round reports: the cached ones,
// and those not seen yet read in one pipeline.
func (s *Store) decodeJobs(ctx context.Context, records []map[string]string) ([]*pb.Job, error) {
	jobs := make([]*pb.Job, len(records))
	have := make([][]*pb.RoundReport, len(records))
	missing := map[int]*redis.StringSliceCmd{}
	var err error
	for i, h := range records {
		if jobs[i], err = decodeJob(h); err != nil {
			return nil, err
		}
		have[i] = s.rounds.get(jobs[i].Id)
		if n := int(number(h["nrounds"])); len(have[i]) < n {
			missing[i] = nil
		}
	}
	if len(missing) > 0 {
		_, err := s.rdb.Pipelined(ctx, func(p redis.Pipeliner) error {
			for i := range missing {
				missing[i] = p.LRange(ctx, s.roundsKey(jobs[i].Id), int64(len(have[i])), int64(number(records[i]["nrounds"]))-1)
			}
			return nil
		})
		if err != nil {
			return nil, redisErr(err)
		}
	}
	for i, j := range jobs {
		rs := have[i]
		if cmd, ok := missing[i]; ok {
			more, err := decodeRounds(j.Id, cmd.Val())
			if err != nil {
				return nil, err
			}
			rs = append(slices.Clone(rs), more...)
			if len(rs) < int(number(records[i]["nrounds"])) {
				return nil, errs.E(errs.Internal, "job %s counts %s round reports but has %d", j.Id, records[i]["nrounds"], len(rs))
			}
			s.rounds.put(j.Id, rs)
		}
		j.Rounds = slices.Clone(rs[:number(records[i]["nrounds"])])
	}
	return jobs, nil
}

func decodeRounds(jobID string, raw []string) ([]*pb.RoundReport, error) {
	out := make([]*pb.RoundReport, len(raw))
	for i, r := range raw {
		out[i] = &pb.RoundReport{}
		if err := proto.Unmarshal([]byte(r), out[i]); err != nil {
			return nil, errs.Wrap(errs.Internal, err, fmt.Sprintf("decode round report of job %s", jobID))
		}
	}
	return out, nil
}
