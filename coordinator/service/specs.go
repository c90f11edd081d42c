package service

import (
	"context"
	"strconv"

	"google.golang.org/protobuf/proto"

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
//
// A round's phases are contiguous ranges of its tasks in stage order, and the task is in
// the job's latest round, whose tasks per phase Job.phases counts: so what a task needs
// is found from its stage (store.Leased's StageStart) by arithmetic, and only the tasks
// it needs are read. Reading from the job's first task, the cost of a round grew with
// the rounds before it.
func (s *Service) fillSpec(ctx context.Context, l *store.Leased) error {
	switch spec := l.Task.GetSpec().(type) {
	case *pb.Task_Composite:
		return s.fillComposite(ctx, l, spec.Composite)
	case *pb.Task_BuildPhotonMap:
		shards, err := s.shards(ctx, l)
		spec.BuildPhotonMap.Shards = shards
		return err
	case *pb.Task_PrecomputeIrradiance:
		return s.fillPrecompute(ctx, l, spec.PrecomputeIrradiance)
	case *pb.Task_MergeIrradiance:
		return s.fillMerge(ctx, l, spec.MergeIrradiance)
	case *pb.Task_RenderTile:
		var err error
		if spec.RenderTile.SampleMap, err = s.sampleMap(ctx, l); err != nil {
			return err
		}
		if phaseTotal(l.Change.Job, pb.Phase_PHASE_BUILD) == 0 {
			return nil
		}
		spec.RenderTile.PhotonSnapshot, err = s.snapshot(ctx, l)
		return err
	}
	return nil
}

// phaseTotal is how many tasks of phase p the job's latest round has.
func phaseTotal(j *pb.Job, p pb.Phase) uint32 {
	for _, ph := range j.GetPhases() {
		if ph.GetPhase() == p {
			return ph.GetTasksTotal()
		}
	}
	return 0
}

// stageBefore returns the range [from, to) of the tasks of phase p in the stage just
// before l's: p's tasks of the round, which precede l's stage.
func stageBefore(l *store.Leased, p pb.Phase) (from, to uint32, err error) {
	n := phaseTotal(l.Change.Job, p)
	if n == 0 || n > l.StageStart {
		return 0, 0, errs.E(errs.Internal, "task %s: its round has %d %s tasks before its stage at %d", l.Task.GetId(), n, p, l.StageStart)
	}
	return l.StageStart - n, l.StageStart, nil
}

// ReadPage is how many tasks a fill reads at a time (the in-memory store copies a page
// under its lock).
const ReadPage = 1000

// outputs calls fn with each task of job jobID in [from, to), in plan order, and its
// output of kind k; every one of them must be of phase p and have succeeded.
func (s *Service) outputs(ctx context.Context, jobID string, from, to uint32, p pb.Phase, k pb.ArtifactKind, fn func(*pb.Task, *pb.Artifact)) error {
	for from < to {
		ts, _, err := s.cfg.Store.ListTasks(ctx, jobID, int(min(to-from, ReadPage)), store.EncodePageToken('t', uint64(from)))
		if err != nil {
			return err
		}
		if len(ts) == 0 {
			return errs.E(errs.Internal, "job %s has no task %d", jobID, from)
		}
		for _, t := range ts {
			if tasks.PhaseOf(t) != p {
				return errs.E(errs.Internal, "task %s is of phase %s, not %s", t.GetId(), tasks.PhaseOf(t), p)
			}
			a, err := output(t, k)
			if err != nil {
				return err
			}
			fn(t, a)
		}
		from += uint32(len(ts))
	}
	return nil
}

// outputOf returns the output of kind k of task index i of job jobID, which must be of
// phase p.
func (s *Service) outputOf(ctx context.Context, jobID string, i uint32, p pb.Phase, k pb.ArtifactKind) (*pb.Artifact, error) {
	var out *pb.Artifact
	err := s.outputs(ctx, jobID, i, i+1, p, k, func(_ *pb.Task, a *pb.Artifact) { out = a })
	return out, err
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

// stageOutputs returns, for each task of phase p in the stage before l's, in plan order,
// what item makes of it and its output of kind k.
func stageOutputs[T any](ctx context.Context, s *Service, l *store.Leased, p pb.Phase, k pb.ArtifactKind, item func(*pb.Task, *pb.Artifact) T) ([]T, error) {
	from, to, err := stageBefore(l, p)
	if err != nil {
		return nil, err
	}
	out := make([]T, 0, to-from)
	err = s.outputs(ctx, l.Task.GetJobId(), from, to, p, k, func(t *pb.Task, a *pb.Artifact) { out = append(out, item(t, a)) })
	return out, err
}

// tiles lists the rectangles and tile EXRs of the render stage before composite l.
func (s *Service) tiles(ctx context.Context, l *store.Leased) ([]*pb.TileInput, error) {
	return stageOutputs(ctx, s, l, pb.Phase_PHASE_RENDER, pb.ArtifactKind_ARTIFACT_KIND_TILE_EXR, func(t *pb.Task, tile *pb.Artifact) *pb.TileInput {
		return &pb.TileInput{Rect: t.GetRenderTile().GetRect(), Tile: tile}
	})
}

// shards lists the emission shards before build l, in plan order, with what each produced.
func (s *Service) shards(ctx context.Context, l *store.Leased) ([]*pb.EmittedShard, error) {
	return stageOutputs(ctx, s, l, pb.Phase_PHASE_EMIT, pb.ArtifactKind_ARTIFACT_KIND_PHOTON_SHARD, func(t *pb.Task, shard *pb.Artifact) *pb.EmittedShard {
		return &pb.EmittedShard{Spec: t.GetEmitPhotons(), Shard: shard}
	})
}

// snapshot returns the photon snapshot the tiles of l's round render with: the output of
// the task just before the render stage, the merge (with irradiance) if the round has one,
// else the build. It is immutable once made, so it is remembered per job and round.
func (s *Service) snapshot(ctx context.Context, l *store.Leased) (*pb.Artifact, error) {
	key := l.Task.GetJobId() + "/" + strconv.FormatUint(uint64(max(l.Task.GetRound(), 1)), 10)
	if a, ok := s.snapshots.get(key); ok {
		return proto.Clone(a).(*pb.Artifact), nil // the caller puts it in a spec
	}
	by := pb.Phase_PHASE_BUILD
	if phaseTotal(l.Change.Job, pb.Phase_PHASE_MERGE) > 0 {
		by = pb.Phase_PHASE_MERGE
	}
	if l.StageStart == 0 {
		return nil, errs.E(errs.Internal, "task %s has a build phase but no stage before it", l.Task.GetId())
	}
	snap, err := s.outputOf(ctx, l.Task.GetJobId(), l.StageStart-1, by, pb.ArtifactKind_ARTIFACT_KIND_PHOTON_SNAPSHOT)
	if err != nil {
		return nil, err
	}
	s.snapshots.put(key, proto.Clone(snap).(*pb.Artifact))
	return snap, nil
}
