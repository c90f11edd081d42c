package service

import (
	"context"

	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// Artifact names of the photon phases (docs/photon-snapshot.md).
const (
	ShardArtifact    = "photons.shard"
	SnapshotArtifact = "photons.snapshot"
	TileArtifact     = "tile.exr"
)

// fillSpec fills in what a leased task needs from the phases before it: a composite its
// tiles, a build its emission shards, a render tile its photon snapshot (if the job has
// one). Earlier phases have all succeeded when a task is leased, so their outputs are final.
func (s *Service) fillSpec(ctx context.Context, l *store.Leased) error {
	task := l.Task
	switch spec := task.GetSpec().(type) {
	case *pb.Task_Composite:
		tiles, err := s.tiles(ctx, task.GetJobId())
		spec.Composite.Tiles = tiles
		return err
	case *pb.Task_BuildPhotonMap:
		shards, err := s.shards(ctx, task.GetJobId())
		spec.BuildPhotonMap.Shards = shards
		return err
	case *pb.Task_RenderTile:
		if !hasPhase(l.Change.Job, pb.Phase_PHASE_BUILD) {
			return nil
		}
		snap, err := s.snapshot(ctx, task.GetJobId())
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
	token := ""
	for {
		tasks, next, err := s.cfg.Store.ListTasks(ctx, jobID, MaxTasksPage, token)
		if err != nil {
			return err
		}
		for _, t := range tasks {
			more, err := fn(t)
			if err != nil || !more {
				return err
			}
		}
		if next == "" {
			return nil
		}
		token = next
	}
}

// output returns a succeeded task's artifact called name.
func output(t *pb.Task, name string) (*pb.Artifact, error) {
	if t.GetState() != pb.TaskState_TASK_STATE_SUCCEEDED {
		return nil, errs.E(errs.Internal, "task %s is %s, not succeeded, though a later phase was leased", t.GetId(), t.GetState())
	}
	for _, o := range t.GetOutputs() {
		if o.GetName() == name {
			return o, nil
		}
	}
	return nil, errs.E(errs.Internal, "task %s succeeded without a %q output", t.GetId(), name)
}

// tiles lists the rectangles and tile EXRs of a job's render phase.
func (s *Service) tiles(ctx context.Context, jobID string) ([]*pb.TileInput, error) {
	var tiles []*pb.TileInput
	err := s.eachTask(ctx, jobID, func(t *pb.Task) (bool, error) {
		rt := t.GetRenderTile()
		if rt == nil {
			return t.GetPhase() < pb.Phase_PHASE_RENDER, nil
		}
		tile, err := output(t, TileArtifact)
		if err != nil {
			return false, err
		}
		tiles = append(tiles, &pb.TileInput{Rect: rt.GetRect(), Tile: tile})
		return true, nil
	})
	return tiles, err
}

// shards lists a job's emission shards, in plan order, with what each produced.
func (s *Service) shards(ctx context.Context, jobID string) ([]*pb.EmittedShard, error) {
	var shards []*pb.EmittedShard
	err := s.eachTask(ctx, jobID, func(t *pb.Task) (bool, error) {
		e := t.GetEmitPhotons()
		if e == nil {
			return t.GetPhase() < pb.Phase_PHASE_EMIT, nil
		}
		shard, err := output(t, ShardArtifact)
		if err != nil {
			return false, err
		}
		shards = append(shards, &pb.EmittedShard{Spec: e, Shard: shard})
		return true, nil
	})
	return shards, err
}

// snapshot returns the photon snapshot a job's build task produced. It is immutable once
// the build succeeded, so it is remembered per job.
func (s *Service) snapshot(ctx context.Context, jobID string) (*pb.Artifact, error) {
	if a, ok := s.snapshots.get(jobID); ok {
		return a, nil
	}
	var snap *pb.Artifact
	err := s.eachTask(ctx, jobID, func(t *pb.Task) (bool, error) {
		if t.GetBuildPhotonMap() == nil {
			return t.GetPhase() < pb.Phase_PHASE_BUILD, nil
		}
		a, err := output(t, SnapshotArtifact)
		snap = a
		return false, err
	})
	if err != nil {
		return nil, err
	}
	if snap == nil {
		return nil, errs.E(errs.Internal, "job %s has a build phase but no build task", jobID)
	}
	s.snapshots.put(jobID, snap)
	return snap, nil
}
