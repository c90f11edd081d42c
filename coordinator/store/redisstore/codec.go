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

// A job record (hash j:{job}) keeps what never changes as one protobuf ("static": the
// pb.Job without state, times other than creation, outputs, phases or rounds) and what
// the scripts change as plain fields:
//
//	seq, state, update     sequence, JobState, last change (µs)
//	end, error, fkind      end time (µs), Job.error, Job.failure_kind
//	outputs                the final artifacts (see encodeArtifacts)
//	prio, held             priority; leases held now (the ready sets' score)
//	b:{worker}             blocked: "{block time µs} {reason}"
//	bkind                  the failure kind of the latest block
//	f:{worker}             the worker's failed attempts at the job's tasks
//	ntasks, nrounds        tasks so far; round reports so far (the list r:{job})
//	cur, curend, left      the current stage [cur, curend) and its tasks not yet succeeded
//	cphase, next           the current stage's phase; its first task never leased
//	pround, pphases        the latest round and its phases in plan order ("5,6")
//	pt:{phase}, ps:{phase} that round's tasks of phase: total, succeeded
//
// A task record (hash t:{job}.{index}) keeps the planner's task as "spec" (the pb.Task
// without id, job, index, state, attempts, worker, error or outputs) and: job, idx, phase,
// round, stage (store.Stage), state (as last written: see jobView.taskState), and, once
// leased (a field not written yet reads as zero or empty), epoch (the fencing token; only
// grows), attempts, failures, expiries, worker, error, fkind (Task.failure_kind), log (the
// last failed attempt's Task.log, a serialized pb.Artifact), outputs,
// expire (µs), retry (µs, or empty: Task.retry_time), progress (the lease's largest
// HeldLease.progress, decimal) and ptime (µs, when it last grew).

// encodeArtifacts stores a list of artifacts as a serialized pb.Task holding only them, so
// that concatenated encodings decode to the concatenated list (protobuf merges repeated
// fields): the completion script joins a stage's outputs without parsing them.
func encodeArtifacts(as []*pb.Artifact) ([]byte, error) {
	return proto.Marshal(&pb.Task{Outputs: as})
}

func decodeArtifacts(b string) ([]*pb.Artifact, error) {
	var t pb.Task
	if err := proto.Unmarshal([]byte(b), &t); err != nil {
		return nil, err
	}
	return t.Outputs, nil
}

// taskArgs is the append section the scripts read: the count, then spec, phase, round
// and stage (store.Stage) of each task.
func taskArgs(tasks []*pb.Task) ([]any, error) {
	args := []any{len(tasks)}
	for _, t := range tasks {
		spec := proto.Clone(t).(*pb.Task)
		spec.Id, spec.JobId, spec.Index, spec.State = "", "", 0, pb.TaskState_TASK_STATE_UNSPECIFIED
		spec.Attempts, spec.WorkerId, spec.Error, spec.Outputs, spec.RetryTime = 0, "", "", nil, nil
		b, err := proto.Marshal(spec)
		if err != nil {
			return nil, errs.Wrap(errs.Internal, err, fmt.Sprintf("encode task %d", t.GetIndex()))
		}
		args = append(args, b, int32(t.GetPhase()), t.GetRound(), strconv.FormatUint(store.Stage(t), 10))
	}
	return args, nil
}

func micros(t time.Time) string { return strconv.FormatInt(t.UnixMicro(), 10) }

func timestamp(us string) *timestamppb.Timestamp {
	n, _ := strconv.ParseInt(us, 10, 64)
	return timestamppb.New(time.UnixMicro(n))
}

func number(s string) uint64 {
	n, _ := strconv.ParseUint(s, 10, 64)
	return n
}

// decodeJob rebuilds a pb.Job from its record, without its round reports (roundCache).
func decodeJob(h map[string]string) (*pb.Job, error) {
	j := &pb.Job{}
	if err := proto.Unmarshal([]byte(h["static"]), j); err != nil {
		return nil, errs.Wrap(errs.Internal, err, "decode job record")
	}
	j.State = pb.JobState(number(h["state"]))
	j.UpdateTime = timestamp(h["update"])
	if h["end"] != "" {
		j.EndTime = timestamp(h["end"])
	}
	j.Error = h["error"]
	j.FailureKind = pb.FailureKind(number(h["fkind"]))
	p, _ := strconv.ParseInt(h["prio"], 10, 32)
	j.Priority = int32(p)
	for k, v := range h {
		if w, ok := strings.CutPrefix(k, blockedField); ok {
			at, reason, _ := strings.Cut(v, " ")
			j.BlockedWorkers = append(j.BlockedWorkers, &pb.BlockedWorker{WorkerId: w, Reason: reason, BlockTime: timestamp(at)})
		}
	}
	store.SortBlocked(j.BlockedWorkers)
	outs, err := decodeArtifacts(h["outputs"])
	if err != nil {
		return nil, errs.Wrap(errs.Internal, err, fmt.Sprintf("decode outputs of job %s", j.Id))
	}
	j.Outputs = outs
	for _, ph := range strings.Split(h["pphases"], ",") {
		if ph == "" {
			continue
		}
		j.Phases = append(j.Phases, &pb.PhaseProgress{
			Phase:          pb.Phase(number(ph)),
			TasksTotal:     uint32(number(h["pt:"+ph])),
			TasksSucceeded: uint32(number(h["ps:"+ph])),
		})
	}
	return j, nil
}

// jobView is what a task's state depends on besides its record: its job's state and
// current stage.
type jobView struct {
	state       pb.JobState
	cur, curend uint64
}

func viewOf(h map[string]string) jobView {
	return jobView{state: pb.JobState(number(h["state"])), cur: number(h["cur"]), curend: number(h["curend"])}
}

// taskState is the state of task index idx whose record says stored: an unfinished task
// of an ended job was cancelled with it, and a waiting one in the current stage is queued
// (the scripts write neither: scripts.go, Stages).
func (v jobView) taskState(stored pb.TaskState, idx uint64) pb.TaskState {
	switch {
	case store.Ended(v.state) && (stored == pb.TaskState_TASK_STATE_WAITING || stored == pb.TaskState_TASK_STATE_QUEUED ||
		stored == pb.TaskState_TASK_STATE_LEASED):
		return pb.TaskState_TASK_STATE_CANCELLED
	case stored == pb.TaskState_TASK_STATE_WAITING && v.cur <= idx && idx < v.curend:
		return pb.TaskState_TASK_STATE_QUEUED
	}
	return stored
}

// decodeTask rebuilds a pb.Task from its record and its job's view.
func decodeTask(h map[string]string, v jobView) (*pb.Task, error) {
	t := &pb.Task{}
	if err := proto.Unmarshal([]byte(h["spec"]), t); err != nil {
		return nil, errs.Wrap(errs.Internal, err, "decode task record")
	}
	t.Index = uint32(number(h["idx"]))
	t.JobId = h["job"]
	t.Id = store.TaskID(t.JobId, t.Index)
	t.State = v.taskState(pb.TaskState(number(h["state"])), uint64(t.Index))
	t.Attempts = uint32(number(h["attempts"]))
	t.WorkerId = h["worker"]
	t.Error = h["error"]
	t.FailureKind = pb.FailureKind(number(h["fkind"]))
	if h["retry"] != "" {
		t.RetryTime = timestamp(h["retry"])
	}
	outs, err := decodeArtifacts(h["outputs"])
	if err != nil {
		return nil, errs.Wrap(errs.Internal, err, fmt.Sprintf("decode outputs of task %s", t.Id))
	}
	t.Outputs = outs
	if h["log"] != "" {
		t.Log = &pb.Artifact{}
		if err := proto.Unmarshal([]byte(h["log"]), t.Log); err != nil {
			return nil, errs.Wrap(errs.Internal, err, fmt.Sprintf("decode log of task %s", t.Id))
		}
	}
	return t, nil
}

// hash turns an HGETALL answer (a flat list, as scripts return it) into a map.
func hash(v any) map[string]string {
	l, _ := v.([]any)
	m := make(map[string]string, len(l)/2)
	for i := 0; i+1 < len(l); i += 2 {
		k, _ := l[i].(string)
		m[k], _ = l[i+1].(string)
	}
	return m
}

// reply is a script's answer decoded: a change and its task record. A repeated report
// decodes to the zero reply, the empty Change the Store contract asks for.
type reply struct {
	change store.Change
	task   map[string]string // the task record behind change.Task
	view   jobView           // of the job record behind change.Job
	none   bool              // nothing to lease
}

// decodeReply decodes the answers described in scripts.go.
func (s *Store) decodeReply(ctx context.Context, v any) (reply, error) {
	l, _ := v.([]any)
	if len(l) == 0 {
		return reply{}, errs.E(errs.Internal, "unexpected script answer %v", v)
	}
	switch l[0] {
	case "NOOP":
		return reply{}, nil
	case "NONE":
		return reply{none: true}, nil
	case "E":
		if len(l) == 4 {
			return reply{}, refusal(l[1], l[2], l[3])
		}
	case "OK":
		if len(l) == 5 {
			return s.decodeOK(ctx, l)
		}
	}
	return reply{}, errs.E(errs.Internal, "unexpected script answer %v", v)
}

func (s *Store) decodeOK(ctx context.Context, l []any) (reply, error) {
	h := hash(l[3])
	jobs, err := s.decodeJobs(ctx, []map[string]string{h})
	if err != nil {
		return reply{}, err
	}
	r := reply{change: store.Change{Job: jobs[0], JobStateChanged: l[1] == int64(1), Queued: l[2] == int64(1)}, view: viewOf(h)}
	if r.task = hash(l[4]); len(r.task) > 0 {
		if r.change.Task, err = decodeTask(r.task, viewOf(h)); err != nil {
			return reply{}, err
		}
	}
	return r, nil
}

func refusal(kind, field, msg any) error {
	k := errs.Internal
	switch kind {
	case "notfound":
		k = errs.NotFound
	case "precondition":
		k = errs.FailedPrecondition
	case "gone":
		k = errs.Unavailable
	}
	f, _ := field.(string)
	return &errs.Error{Kind: k, Field: f, Message: fmt.Sprint(msg)}
}
