package redisstore

import (
	"context"
	"fmt"
	"strconv"
	"strings"
	"time"

	"google.golang.org/protobuf/proto"
	"google.golang.org/protobuf/types/known/timestamppb"

	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// Jobs and rounds are written in chunks (scripts.go, beginScript), each a script of at
// most StageChunk tasks or StageChunkBytes of arguments: a millisecond or two of Redis.
const (
	StageChunk      = 128
	StageChunkBytes = 256 << 10
)

// CreateJob implements store.Store in bounded steps: the record, the tasks a chunk at a
// time, then the job made visible. A retry with the same request id after a failure
// midway finishes the job the first attempt began.
func (s *Store) CreateJob(ctx context.Context, nj store.NewJob) (*pb.Job, error) {
	if err := nj.Check(); err != nil {
		return nil, err
	}
	id := store.NewJobID()
	static, err := proto.Marshal(&pb.Job{
		Id:          id,
		DisplayName: nj.DisplayName,
		CreateTime:  timestamppb.New(s.opts.Clock.Now()),
		SceneDigest: nj.SceneDigest,
		Width:       nj.Width,
		Height:      nj.Height,
		Plan:        nj.Plan,
	})
	if err != nil {
		return nil, errs.Wrap(errs.Internal, err, "encode job")
	}
	v, err := s.run(ctx, beginScript, id, nj.RequestID, static, nj.Priority, len(nj.Tasks), nj.SceneDigest)
	if err != nil {
		return nil, err
	}
	if l, _ := v.([]any); len(l) == 2 && l[0] == "BUILD" {
		id, _ = l[1].(string)
	} else {
		r, err := s.decodeReply(ctx, v) // the job a request id made before
		return r.change.Job, err
	}
	if _, err := s.stage(ctx, id, id, nil, 0, nj.Tasks); err != nil {
		return nil, err
	}
	stages, counts, round := summary(nj.Tasks, 0)
	r, err := s.change(ctx, publishScript, id, stages, counts, round)
	return r.change.Job, err
}

// stage writes tasks as job jobID's tasks from index base on, in chunks, for owner (the
// job id, or the composite's "task@epoch" whose lease ref is); it reports false if ref's
// report was accepted before, so that there is nothing to stage.
func (s *Store) stage(ctx context.Context, jobID, owner string, ref *store.LeaseRef, base uint32, tasks []*pb.Task) (bool, error) {
	lease := []any{"", "", ""}
	if ref != nil {
		lease = refArgs(*ref)
	}
	for from := 0; from < len(tasks); {
		chunk, bytes := 0, 0
		for from+chunk < len(tasks) && chunk < StageChunk && bytes < StageChunkBytes {
			bytes += proto.Size(tasks[from+chunk])
			chunk++
		}
		args, err := taskArgs(tasks[from : from+chunk])
		if err != nil {
			return false, err
		}
		v, err := s.run(ctx, stageScript, append([]any{jobID, owner, lease[0], lease[1], lease[2], int(base) + from}, args...)...)
		if err != nil {
			return false, err
		}
		if l, _ := v.([]any); len(l) == 1 && l[0] == "NOOP" {
			return false, nil
		} else if len(l) != 1 || l[0] != "STAGED" {
			_, err := s.decodeReply(ctx, v)
			return false, err
		}
		from += chunk
	}
	return true, nil
}

// summary describes tasks numbered from base for the scripts' addtasks: their stages as
// "start:end" ranges, and the last round and its tasks per phase as "phase:count", in
// plan order.
func summary(tasks []*pb.Task, base uint32) (stages, counts string, round uint32) {
	var sb, cb strings.Builder
	start := 0
	for i := range tasks {
		if i+1 == len(tasks) || store.Stage(tasks[i+1]) != store.Stage(tasks[start]) {
			fmt.Fprintf(&sb, "%d:%d,", int(base)+start, int(base)+i+1)
			start = i + 1
		}
	}
	round = tasks[len(tasks)-1].GetRound()
	n := 0
	for i, t := range tasks {
		if t.GetRound() != round {
			continue
		}
		n++
		if i+1 == len(tasks) || tasks[i+1].GetPhase() != t.GetPhase() {
			cb.WriteString(strconv.Itoa(int(t.GetPhase())) + ":" + strconv.Itoa(n) + ",")
			n = 0
		}
	}
	return sb.String(), cb.String(), round
}

// PurgeJobs implements store.Store: one purgeScript, about budget keys deleted.
func (s *Store) PurgeJobs(ctx context.Context, endedBefore, abandonedBefore time.Time, budget int) (store.Purge, error) {
	v, err := s.run(ctx, purgeScript, micros(endedBefore), micros(abandonedBefore), max(budget, 1))
	if err != nil {
		return store.Purge{}, err
	}
	l, _ := v.([]any)
	if len(l) == 0 {
		return store.Purge{}, errs.E(errs.Internal, "unexpected purge answer %v", v)
	}
	p := store.Purge{More: l[0] == int64(1)}
	for _, x := range l[1:] {
		id, _ := x.(string)
		s.rounds.forget(id)
		p.Deleted = append(p.Deleted, id)
	}
	return p, nil
}
