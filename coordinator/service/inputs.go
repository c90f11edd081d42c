package service

import (
	"context"
	"errors"
	"fmt"

	"photonfarm/contract/tasks"
	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// Lost inputs: a blob a task reads that the blob store does not have (lost from disk, or
// a coordinator started on another data folder) or holds damaged. No attempt at the task
// can succeed, so its job fails at once, naming the blob and what it holds, and leasing
// goes on with the other jobs' tasks.

// lostInput is the error of a task input the blob store cannot give.
type lostInput struct {
	what, digest string
	err          error // the store's: errs.NotFound or errs.DataLoss
}

func (e *lostInput) Error() string {
	if errs.Is(e.err, errs.NotFound) {
		return fmt.Sprintf("%s: blob %s is not in the coordinator's blob store", e.what, e.digest)
	}
	var d *errs.Error
	if errors.As(e.err, &d) && d.Kind == errs.DataLoss {
		return e.what + ": " + d.Message
	}
	return e.what + ": " + e.err.Error()
}

func (e *lostInput) Unwrap() error { return e.err }

// lost makes err, the blob store's answer about the blob digest holding what, a
// *lostInput if it says the blob is missing or damaged; other errors pass unchanged.
func lost(what, digest string, err error) error {
	if errs.Is(err, errs.NotFound) || errs.Is(err, errs.DataLoss) {
		return &lostInput{what: what, digest: digest, err: err}
	}
	return err
}

// checkInputs makes sure every blob a leased task reads is in the blob store: the scene
// (which a builder's task does not read) and the blobs its filled-in spec names
// (tasks.Inputs). Only presence is checked here, which costs a stat per blob; damage is
// found where the bytes are read (the builder, DownloadBlob), and the reader fails the
// task as lost input then.
func (s *Service) checkInputs(ctx context.Context, l *store.Leased) error {
	if ph, ok := tasks.Phases.Of(l.Task.GetPhase()); ok && ph.Executor == pb.Executor_EXECUTOR_WORKER {
		if _, err := s.cfg.Blobs.Stat(ctx, l.SceneDigest); err != nil {
			return lost("the scene", l.SceneDigest, err)
		}
	}
	for _, in := range tasks.Inputs(l.Task) {
		d := in.Artifact.GetDigest()
		if _, err := s.cfg.Blobs.Stat(ctx, d); err != nil {
			return lost(in.What, d, err)
		}
	}
	return nil
}

// failLostInput fails the leased task ref, and so its job, for the lost input e (a
// permanent failure: no worker is blamed).
func (s *Service) failLostInput(ctx context.Context, ref store.LeaseRef, e *lostInput) error {
	c, err := s.cfg.Store.FailTask(ctx, ref, store.Failure{Message: e.Error(), Kind: pb.FailureKind_FAILURE_KIND_LOST_INPUT})
	if err != nil {
		return err
	}
	s.cfg.Metrics.TaskFailed()
	s.log.Error("job failed: lost input", "job", c.Job.GetId(), "task", ref.TaskID, "blob", e.digest, "error", e.Error())
	s.publish(c)
	return nil
}
