package service

import (
	"context"

	"photonfarm/contract/tasks"
	"photonfarm/coordinator/blobstore"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// Lost inputs: a blob a task reads that the blob store does not have (lost from disk, or
// a coordinator started on another data folder) or holds damaged. No attempt at the task
// can succeed, so its job fails at once, naming the blob and what it holds, and leasing
// goes on with the other jobs' tasks.

// checkInputs makes sure every blob a leased task reads is in the blob store: the scene
// (which a builder's task does not read) and the blobs its filled-in spec names
// (tasks.Inputs). Only presence is checked here, which costs a stat per blob; damage is
// found where the bytes are read (the builder, DownloadBlob), and the reader fails the
// task as lost input then.
func (s *Service) checkInputs(ctx context.Context, l *store.Leased) error {
	if ph, ok := tasks.Phases.Of(l.Task.GetPhase()); ok && ph.Executor == pb.Executor_EXECUTOR_WORKER {
		if _, err := s.cfg.Blobs.Stat(ctx, l.SceneDigest); err != nil {
			return blobstore.Lost("the scene", l.SceneDigest, err)
		}
	}
	for _, in := range tasks.Inputs(l.Task) {
		d := in.Artifact.GetDigest()
		if _, err := s.cfg.Blobs.Stat(ctx, d); err != nil {
			return blobstore.Lost(in.What, d, err)
		}
	}
	return nil
}

// failLostInput fails the leased task ref, and so its job, for the lost input e (a
// permanent failure: no worker is blamed).
func (s *Service) failLostInput(ctx context.Context, ref store.LeaseRef, e *blobstore.LostError) error {
	c, err := s.cfg.Store.FailTask(ctx, ref, store.Failure{Message: e.Error(), Kind: pb.FailureKind_FAILURE_KIND_LOST_INPUT})
	if err != nil {
		return err
	}
	s.cfg.Metrics.TaskFailed()
	s.log.Error("job failed: lost input", "job", c.Job.GetId(), "task", ref.TaskID, "blob", e.Digest, "error", e.Error())
	s.publish(c)
	return nil
}
