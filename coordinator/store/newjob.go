package store

import (
	"crypto/rand"
	"encoding/hex"

	"photonfarm/contract/tasks"
	"photonfarm/coordinator/errs"
	pb "photonfarm/proto/renderfarm/v1"
)

// NewJobID returns a fresh random job id: "j-" and 16 hex digits.
func NewJobID() string {
	var b [8]byte
	_, _ = rand.Read(b[:])
	return "j-" + hex.EncodeToString(b[:])
}

// Check refuses a NewJob no store should create: without tasks, with a priority out of
// range, or with tasks that are not a plan (CheckPlan).
func (nj NewJob) Check() error {
	if len(nj.Tasks) == 0 {
		return errs.E(errs.InvalidArgument, "a job needs at least one task")
	}
	if err := CheckPriority(nj.Priority); err != nil {
		return err
	}
	return CheckPlan(nj.Tasks)
}

// CheckPlan refuses tasks that are not numbered from 0 in order, whose phase is not the
// one their spec implies (the spec's task_phase), or whose stages go backwards: a planner
// bug, so Internal.
func CheckPlan(ts []*pb.Task) error {
	for i, t := range ts {
		if t.GetIndex() != uint32(i) {
			return errs.E(errs.Internal, "task %d has index %d", i, t.GetIndex())
		}
		if spec := tasks.PhaseOf(t); spec != t.GetPhase() {
			return errs.E(errs.Internal, "task %d is of phase %s but its spec is of %s", i, t.GetPhase(), spec)
		}
		if i > 0 && Stage(t) < Stage(ts[i-1]) {
			return errs.E(errs.Internal, "task %d: phases out of order", i)
		}
	}
	return nil
}
