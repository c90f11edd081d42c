package service

import (
	"context"
	"fmt"
	"math"

	"google.golang.org/protobuf/proto"

	"photonfarm/contract/rules"
	"photonfarm/contract/scene"
	"photonfarm/contract/tasks"
	"photonfarm/coordinator/blobstore"
	"photonfarm/coordinator/errs"
	"photonfarm/coordinator/planner"
	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// Progressive rounds: what the precompute, merge and composite tasks are given when
// leased, and what happens when a round's composite completes.

// fillComposite gives a composite its round's tiles, the previous round's accumulation,
// the round's sample map under adaptive sampling, the scene's reference image and the time
// the job has taken so far.
func (s *Service) fillComposite(ctx context.Context, l *store.Leased, spec *pb.CompositeSpec) error {
	spec.ElapsedSeconds = s.cfg.Clock.Now().Sub(l.Change.Job.GetCreateTime().AsTime()).Seconds()
	tiles, err := s.tiles(ctx, l)
	if err != nil {
		return err
	}
	spec.Tiles = tiles
	if max(l.Task.GetRound(), 1) > 1 {
		prev, err := previousComposite(l)
		if err != nil {
			return err
		}
		spec.PreviousAccumulation, err = s.outputOf(ctx, l.Task.GetJobId(), prev, pb.Phase_PHASE_COMPOSITE, pb.ArtifactKind_ARTIFACT_KIND_ACCUMULATION_EXR)
		if err != nil {
			return err
		}
	}
	if spec.SampleMap, err = s.sampleMap(ctx, l); err != nil {
		return err
	}
	sc, err := s.scene(ctx, l.SceneDigest)
	if err != nil {
		return blobstore.Lost("the scene", l.SceneDigest, err)
	}
	if d := scene.ReferenceDigest(sc); d != "" {
		info, err := s.cfg.Blobs.Stat(ctx, d)
		if err != nil {
			return blobstore.Lost("the reference image", d, err)
		}
		spec.Reference = &pb.Artifact{Name: "reference.exr", Digest: d, SizeBytes: info.Size}
	}
	return nil
}

// previousComposite returns the index of the previous round's composite: the task just
// before the first of l's round, which is as many tasks before l's stage as the round has
// of the phases that run before l's.
func previousComposite(l *store.Leased) (uint32, error) {
	rank := tasks.Rank(tasks.PhaseOf(l.Task))
	var before uint32
	for _, ph := range l.Change.Job.GetPhases() {
		if tasks.Rank(ph.GetPhase()) < rank {
			before += ph.GetTasksTotal()
		}
	}
	if before >= l.StageStart {
		return 0, errs.E(errs.Internal, "task %s of round %d has no round before it", l.Task.GetId(), l.Task.GetRound())
	}
	return l.StageStart - before - 1, nil
}

// sampleMap returns, for a render tile or composite of a round that allocates its camera
// samples by error (scene.Adaptive, from round scene.AdaptiveFrom), the sample map the
// previous round's composite made; nil for any other round.
func (s *Service) sampleMap(ctx context.Context, l *store.Leased) (*pb.Artifact, error) {
	if max(l.Task.GetRound(), 1) < scene.AdaptiveFrom {
		return nil, nil
	}
	sc, err := s.scene(ctx, l.SceneDigest)
	if err != nil {
		return nil, blobstore.Lost("the scene", l.SceneDigest, err)
	}
	if on, _ := scene.Adaptive(sc); !on {
		return nil, nil
	}
	prev, err := previousComposite(l)
	if err != nil {
		return nil, err
	}
	return s.outputOf(ctx, l.Task.GetJobId(), prev, pb.Phase_PHASE_COMPOSITE, pb.ArtifactKind_ARTIFACT_KIND_SAMPLE_MAP)
}

// fillPrecompute gives precompute task i of the round's K (its place in its stage) its
// part, i of K, of the global map's irradiance sites (how many the worker derives from the
// snapshot and the round's estimate, docs/photon-snapshot.md) and the round's built
// snapshot, the output of the build just before the stage, verified first.
func (s *Service) fillPrecompute(ctx context.Context, l *store.Leased, spec *pb.PrecomputeIrradianceSpec) error {
	if l.StageStart == 0 {
		return errs.E(errs.Internal, "precompute task %s has no build before it", l.Task.GetId())
	}
	snap, err := s.outputOf(ctx, l.Task.GetJobId(), l.StageStart-1, pb.Phase_PHASE_BUILD, pb.ArtifactKind_ARTIFACT_KIND_PHOTON_SNAPSHOT)
	if err != nil {
		return err
	}
	if err := s.verifySnapshot(ctx, snap); err != nil {
		return blobstore.Lost(fmt.Sprintf("the photon snapshot of round %d", max(l.Task.GetRound(), 1)), snap.GetDigest(), err)
	}
	spec.Part, spec.Parts = l.Task.GetIndex()-l.StageStart, l.StageEnd-l.StageStart
	spec.PhotonSnapshot = snap
	return nil
}

// fillMerge gives the merge the round's built snapshot and irradiance shards in plan order:
// the precompute stage before it, and the build before that.
func (s *Service) fillMerge(ctx context.Context, l *store.Leased, spec *pb.MergeIrradianceSpec) error {
	from, _, err := stageBefore(l, pb.Phase_PHASE_PRECOMPUTE)
	if err != nil {
		return err
	}
	if from == 0 {
		return errs.E(errs.Internal, "merge task %s has no build before it", l.Task.GetId())
	}
	if spec.PhotonSnapshot, err = s.outputOf(ctx, l.Task.GetJobId(), from-1, pb.Phase_PHASE_BUILD, pb.ArtifactKind_ARTIFACT_KIND_PHOTON_SNAPSHOT); err != nil {
		return err
	}
	spec.IrradianceShards, err = stageOutputs(ctx, s, l, pb.Phase_PHASE_PRECOMPUTE, pb.ArtifactKind_ARTIFACT_KIND_IRRADIANCE_SHARD, func(_ *pb.Task, a *pb.Artifact) *pb.Artifact {
		return a
	})
	return err
}

// verifySnapshot checks a snapshot whole before the round's precompute tasks fetch it:
// damage found here fails the job naming it before any worker spends time on it. Once per
// digest (a blob never changes).
func (s *Service) verifySnapshot(ctx context.Context, snap *pb.Artifact) error {
	d := snap.GetDigest()
	if _, ok := s.verifiedSnapshots.get(d); ok {
		return nil
	}
	if _, err := s.verifiedBlob(ctx, d); err != nil {
		return err
	}
	s.verifiedSnapshots.put(d, struct{}{})
	return nil
}

// scene returns the stored scene with this digest (defaults filled in at submit),
// remembered by digest: a stored scene never changes. A missing or damaged blob is the
// blob store's error (errs.NotFound, errs.DataLoss).
func (s *Service) scene(ctx context.Context, digest string) (*pb.Scene, error) {
	if sc, ok := s.scenes.get(digest); ok {
		return sc, nil
	}
	r, info, err := s.cfg.Blobs.Open(ctx, digest)
	if err != nil {
		return nil, err
	}
	defer r.Close()
	data, err := blobstore.ReadAll(r, info.Size)
	if err != nil {
		return nil, err
	}
	sc := &pb.Scene{}
	if err := proto.Unmarshal(data, sc); err != nil {
		return nil, errs.Wrap(errs.Internal, err, fmt.Sprintf("scene %s", digest))
	}
	s.scenes.put(digest, sc)
	return sc, nil
}

// checkMetrics refuses metrics that are not finite and >= 0, layer errors of layers a
// render does not have, and an error estimate's parts out of order (its bias above it, or
// it outside its interval).
func checkMetrics(m *pb.RoundMetrics) error {
	type value struct {
		field string
		set   bool
		v     float64
	}
	values := []value{
		{"metrics.error_estimate", m.ErrorEstimate != nil, m.GetErrorEstimate()},
		{"metrics.reference_rmse", m.ReferenceRmse != nil, m.GetReferenceRmse()},
		{"metrics.error_estimate_bias", m.ErrorEstimateBias != nil, m.GetErrorEstimateBias()},
		{"metrics.error_estimate_low", m.ErrorEstimateLow != nil, m.GetErrorEstimateLow()},
		{"metrics.error_estimate_high", m.ErrorEstimateHigh != nil, m.GetErrorEstimateHigh()},
	}
	// The contract's rules first: the layers measured are layer_reference_rmse's keys.
	if fe := rules.Check(m); fe != nil {
		return errs.Field("metrics."+fe.Field, "%s", fe.Message)
	}
	for layer, v := range m.GetLayerReferenceRmse() {
		values = append(values, value{fmt.Sprintf("metrics.layer_reference_rmse[%s]", layer), true, v})
	}
	if sp := m.GetSamples(); sp != nil {
		values = append(values, value{"metrics.samples.mean", true, sp.GetMean()}, value{"metrics.samples.top_error_decile_share", sp.TopErrorDecileShare != nil, sp.GetTopErrorDecileShare()})
	}
	for _, v := range values {
		if v.set && (math.IsNaN(v.v) || math.IsInf(v.v, 0) || v.v < 0) {
			return errs.Field(v.field, "must be a finite number >= 0, got %v", v.v)
		}
	}
	if err := checkEstimateParts(m); err != nil {
		return err
	}
	return checkSpread(m.GetSamples())
}

// checkEstimateParts refuses an error estimate's bias, low or high without the estimate,
// a bias above it, or an interval that does not hold it.
func checkEstimateParts(m *pb.RoundMetrics) error {
	parts := m.ErrorEstimateBias != nil || m.ErrorEstimateLow != nil || m.ErrorEstimateHigh != nil
	switch e := m.GetErrorEstimate(); {
	case parts && m.ErrorEstimate == nil:
		return errs.Field("metrics.error_estimate", "must be set with its bias and interval")
	case m.ErrorEstimateBias != nil && m.GetErrorEstimateBias() > e:
		return errs.Field("metrics.error_estimate_bias", "must be at most error_estimate %v, got %v", e, m.GetErrorEstimateBias())
	case m.ErrorEstimateLow != nil && m.GetErrorEstimateLow() > e:
		return errs.Field("metrics.error_estimate_low", "must be at most error_estimate %v, got %v", e, m.GetErrorEstimateLow())
	case m.ErrorEstimateHigh != nil && m.GetErrorEstimateHigh() < e:
		return errs.Field("metrics.error_estimate_high", "must be at least error_estimate %v, got %v", e, m.GetErrorEstimateHigh())
	}
	return nil
}

// checkSpread refuses a sample spread that cannot be: no layer name, min > mean > max, or
// a share above 1.
func checkSpread(sp *pb.SampleSpread) error {
	switch {
	case sp == nil:
		return nil
	case sp.GetLayer() == "" || len(sp.GetLayer()) > 255:
		return errs.Field("metrics.samples.layer", "must be 1 to 255 bytes, got %d", len(sp.GetLayer()))
	case float64(sp.GetMin()) > sp.GetMean() || sp.GetMean() > float64(sp.GetMax()):
		return errs.Field("metrics.samples", "min %d, mean %v and max %d are not in order", sp.GetMin(), sp.GetMean(), sp.GetMax())
	case sp.GetTopErrorDecileShare() > 1:
		return errs.Field("metrics.samples.top_error_decile_share", "must be at most 1, got %v", sp.GetTopErrorDecileShare())
	}
	return nil
}

// roundEnd decides what follows the composite of task's round: the report of the round,
// and the next round's tasks or, if the job stops here, its final outputs.
func (s *Service) roundEnd(ctx context.Context, task *pb.Task, outputs []*pb.Artifact, m *pb.RoundMetrics) (store.RoundEnd, string, error) {
	job, err := s.cfg.Store.GetJob(ctx, task.GetJobId())
	if err != nil {
		return store.RoundEnd{}, "", err
	}
	sc, err := s.scene(ctx, job.GetSceneDigest())
	if err != nil {
		return store.RoundEnd{}, "", blobstore.Lost("the scene", job.GetSceneDigest(), err)
	}
	round := max(task.GetRound(), 1)
	report := &pb.RoundReport{
		Round:              round,
		ElapsedSeconds:     s.cfg.Clock.Now().Sub(job.GetCreateTime().AsTime()).Seconds(),
		Photons:            uint64(round) * planner.PhotonsPerRound(sc),
		SamplesPerPixel:    uint64(round) * uint64(scene.SamplesPerPixel(sc)),
		ErrorEstimate:      m.ErrorEstimate,
		ErrorEstimateBias:  m.ErrorEstimateBias,
		ErrorEstimateLow:   m.ErrorEstimateLow,
		ErrorEstimateHigh:  m.ErrorEstimateHigh,
		ReferenceRmse:      m.ReferenceRmse,
		LayerReferenceRmse: m.GetLayerReferenceRmse(),
		Samples:            m.GetSamples(),
	}
	end := store.RoundEnd{Outputs: outputs, Report: report}
	why := StopReason(sc, report)
	if why == "" {
		end.Next = planner.Round(sc, round+1)
		return end, "", nil
	}
	for _, o := range outputs {
		if !notFinal[o.GetName()] {
			end.Final = append(end.Final, o)
		}
	}
	return end, why, nil
}

// notFinal names the composite's outputs that a job's final outputs leave out: those only
// the next round reads, and the composite's own log (on the task).
var notFinal = map[string]bool{
	tasks.ArtifactName(pb.ArtifactKind_ARTIFACT_KIND_ACCUMULATION_EXR): true,
	tasks.ArtifactName(pb.ArtifactKind_ARTIFACT_KIND_SAMPLE_MAP):       true,
	tasks.ArtifactName(pb.ArtifactKind_ARTIFACT_KIND_TASK_LOG):         true,
}

// StopReason says why a progressive job stops after the round of report, or "" if it goes
// on: max_rounds reached, the error (against the reference if the scene names one, else
// the estimate from the spread between rounds) at most target_error, or the time budget
// spent.
func StopReason(sc *pb.Scene, report *pb.RoundReport) string {
	p := sc.GetProgressive()
	if report.GetRound() >= scene.Rounds(sc) {
		return fmt.Sprintf("max rounds (%d) reached", scene.Rounds(sc))
	}
	if t := p.GetTargetError(); t > 0 {
		if scene.ReferenceDigest(sc) != "" {
			if report.ReferenceRmse != nil && report.GetReferenceRmse() <= t {
				return fmt.Sprintf("reference RMSE %.4g <= target %g", report.GetReferenceRmse(), t)
			}
		} else if report.ErrorEstimate != nil && report.GetErrorEstimate() <= t {
			return fmt.Sprintf("error estimate %.4g <= target %g", report.GetErrorEstimate(), t)
		}
	}
	if b := p.GetTimeBudgetSeconds(); b > 0 && report.GetElapsedSeconds() >= b {
		return fmt.Sprintf("time budget %gs spent (%.1fs)", b, report.GetElapsedSeconds())
	}
	return ""
}
