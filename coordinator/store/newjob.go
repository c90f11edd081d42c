package store

import (
	"crypto/rand"
	"encoding/hex"

	"photonfarm/coordinator/errs"
)

// NewJobID returns a fresh random job id: "j-" and 16 hex digits.
func NewJobID() string {
	var b [8]byte
	_, _ = rand.Read(b[:])
	return "j-" + hex.EncodeToString(b[:])
}

// Check refuses a NewJob no store should create: without tasks, with a priority out of
// range, or with tasks out of plan order (a planner bug, so Internal).
func (nj NewJob) Check() error {
	if len(nj.Tasks) == 0 {
		return errs.E(errs.InvalidArgument, "a job needs at least one task")
	}
	if err := CheckPriority(nj.Priority); err != nil {
		return err
	}
	for i, t := range nj.Tasks {
		if t.GetIndex() != uint32(i) {
			return errs.E(errs.Internal, "task %d has index %d", i, t.GetIndex())
		}
		if i > 0 && Stage(t) < Stage(nj.Tasks[i-1]) {
			return errs.E(errs.Internal, "task %d: phases out of order", i)
		}
	}
	return nil
}
