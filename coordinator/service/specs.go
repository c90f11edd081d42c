package service

import (
	"cmp"
	"context"
	"strconv"

	"google.golang.org/protobuf/proto"

	"photonfarm/contract/pages"
	"photonfarm/contract/tasks"
	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// fillSpec fills in what a leased task needs from the stages before it, all of its own
// round except the previous round's accumulation: a build its emission shards, a
// precompute its photon range and snapshot, a merge the snapshot and irradiance shards, a
// render tile its photon snapshot (if the job has one), a composite its tiles, the
// previous accumulation and the reference image. Earlier stages have all succeeded when a
// task is leased, so their outputs are final.
func (s *Service) fillSpec(ctx context.Context, l *store.Leased) error {
	task := l.Task
	jobID, round := task.GetJobId(), max(task.GetRound(), 1)
	switch spec := task.GetSpec().(type) {
	case *pb.Task_Composite:
		return s.fillComposite(ctx, l, spec.Composite)
	case *pb.Task_BuildPhotonMap:
		shards, err := s.shards(ctx, jobID, round)
		spec.BuildPhotonMap.Shards = shards
		return err
	case *pb.Task_PrecomputeIrradiance:
		return s.fillPrecompute(ctx, task, spec.PrecomputeIrradiance)
	case *pb.Task_MergeIrradiance:
		return s.fillMerge(ctx, task, spec.MergeIrradiance)
	case *pb.Task_RenderTile:
		if !hasPhase(l.Change.Job, pb.Phase_PHASE_BUILD) {
			return nil
		}
		snap, err := s.snapshot(ctx, jobID, round)
		spec.RenderTile.PhotonSnapshot = snap
		return err
	}
	return nil
}

func hasPhase(j *pb.Job, p pb.Phase) bool {
	for _, ph := range j.GetPhases() {
		if ph.GetPhase() == p {
			return true
		}
	}
	return false
}

// eachTask calls fn with a job's tasks in plan order until it returns false.
func (s *Service) eachTask(ctx context.Context, jobID string, fn func(*pb.Task) (more bool, err error)) error {
	return pages.Each(func(token string) ([]*pb.Task, string, error) {
		return s.cfg.Store.ListTasks(ctx, jobID, MaxTasksPage, token)
	}, fn)
}

// output returns a succeeded task's artifact of kind k.
func output(t *pb.Task, k pb.ArtifactKind) (*pb.Artifact, error) {
	if t.GetState() != pb.TaskState_TASK_STATE_SUCCEEDED {
		return nil, errs.E(errs.Internal, "task %s is %s, not succeeded, though a later phase was leased", t.GetId(), t.GetState())
	}
	if a := tasks.Find(t.GetOutputs(), k); a != nil {
		return a, nil
	}
	return nil, errs.E(errs.Internal, "task %s succeeded without a %q output", t.GetId(), tasks.ArtifactName(k))
}

// roundTasks calls fn with the tasks of one round of a job, in plan order.
func (s *Service) roundTasks(ctx context.Context, jobID string, round uint32, fn func(*pb.Task) error) error {
	return s.eachTask(ctx, jobID, func(t *pb.Task) (bool, error) {
		r := max(t.GetRound(), 1)
		if r == round {
			if err := fn(t); err != nil {
				return false, err
			}
		}
		return r <= round, nil
	})
}

// roundOutputs calls fn with each task of phase p in one round of a job, in plan order,
// and the task's output of kind k.
func (s *Service) roundOutputs(ctx context.Context, jobID string, round uint32, p pb.Phase, k pb.ArtifactKind, fn func(*pb.Task, *pb.Artifact)) error {
	return s.roundTasks(ctx, jobID, round, func(t *pb.Task) error {
		if tasks.PhaseOf(t) != p {
			return nil
		}
		a, err := output(t, k)
		if err == nil {
			fn(t, a)
		}
		return err
	})
}

// tiles lists the rectangles and tile EXRs of a round's render phase.
func (s *Service) tiles(ctx context.Context, jobID string, round uint32) ([]*pb.TileInput, error) {
	var tiles []*pb.TileInput
	err := s.roundOutputs(ctx, jobID, round, pb.Phase_PHASE_RENDER, pb.ArtifactKind_ARTIFACT_KIND_TILE_EXR, func(t *pb.Task, tile *pb.Artifact) {
		tiles = append(tiles, &pb.TileInput{Rect: t.GetRenderTile().GetRect(), Tile: tile})
	})
	return tiles, err
}

// shards lists a round's emission shards, in plan order, with what each produced.
func (s *Service) shards(ctx context.Context, jobID string, round uint32) ([]*pb.EmittedShard, error) {
	var shards []*pb.EmittedShard
	err := s.roundOutputs(ctx, jobID, round, pb.Phase_PHASE_EMIT, pb.ArtifactKind_ARTIFACT_KIND_PHOTON_SHARD, func(t *pb.Task, shard *pb.Artifact) {
		shards = append(shards, &pb.EmittedShard{Spec: t.GetEmitPhotons(), Shard: shard})
	})
	return shards, err
}

// builtSnapshot returns the snapshot a round's build task produced (without irradiance).
func (s *Service) builtSnapshot(ctx context.Context, jobID string, round uint32) (*pb.Artifact, error) {
	var snap *pb.Artifact
	err := s.roundOutputs(ctx, jobID, round, pb.Phase_PHASE_BUILD, pb.ArtifactKind_ARTIFACT_KIND_PHOTON_SNAPSHOT, func(_ *pb.Task, a *pb.Artifact) {
		snap = a
	})
	if err == nil && snap == nil {
		err = errs.E(errs.Internal, "job %s round %d has no build task", jobID, round)
	}
	return snap, err
}

// snapshot returns the photon snapshot a round's tiles render with: the merge's (with
// irradiance) if the round has one, else the build's. It is immutable once made, so it is
// remembered per job and round.
func (s *Service) snapshot(ctx context.Context, jobID string, round uint32) (*pb.Artifact, error) {
	key := jobID + "/" + strconv.FormatUint(uint64(round), 10)
	if a, ok := s.snapshots.get(key); ok {
		return proto.Clone(a).(*pb.Artifact), nil // the caller puts it in a spec
	}
	var built, merged *pb.Artifact
	err := s.roundTasks(ctx, jobID, round, func(t *pb.Task) error {
		var err error
		switch {
		case t.GetBuildPhotonMap() != nil:
			built, err = output(t, pb.ArtifactKind_ARTIFACT_KIND_PHOTON_SNAPSHOT)
		case t.GetMergeIrradiance() != nil:
			merged, err = output(t, pb.ArtifactKind_ARTIFACT_KIND_PHOTON_SNAPSHOT)
		}
		return err
	})
	if err != nil {
		return nil, err
	}
	snap := cmp.Or(merged, built)
	if snap == nil {
		return nil, errs.E(errs.Internal, "job %s round %d has a build phase but no build task", jobID, round)
	}
	s.snapshots.put(key, proto.Clone(snap).(*pb.Artifact))
	return snap, nil
}
