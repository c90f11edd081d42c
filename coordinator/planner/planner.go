// Package planner decides what a validated scene needs and splits it into the tasks of a
// job, round by round. Each progressive round r (from 1) has these phases:
//
//   - emit: photon-emission shards of PhotonMapping.photons_per_shard paths (the last one
//     partial), first for the global map (if diffuse surfaces can light each other), then
//     for the caustic map (only if some shape is specular: mirror, dielectric, conductor),
//     then for the volume map (only if some medium scatters light).
//     Round r traces path indices [(r-1)·N, r·N) of each map of N paths, so every round's
//     photons are fresh; total_photons is N (each round's map stands alone);
//   - build: one task merging the round's shards into a kd-tree snapshot;
//   - precompute: with final gathering, as many irradiance tasks as the round has global
//     emission shards. The global map's stored photon count is known only once the build
//     has run, so each task's photon range is filled in when it is leased: task i of K
//     covers [n·i/K, n·(i+1)/K) of the n stored photons (empty ranges are cheap);
//   - merge: one task merging the irradiance shards into the snapshot (coordinator);
//   - render: one RENDER_TILE task per tile, row-major, the last row and column partial,
//     with the round's first pixel sample and search-radius scale;
//   - composite: one COMPOSITE task, which also folds the round into the running mean.
//
// Planning is deterministic: the same scene always gives the same plan.
package planner

import (
	"math"

	"photonfarm/contract/scene"
	pb "photonfarm/proto/renderfarm/v1"
)

// Plan returns the tasks of a job's first round for s (Round(s, 1)).
func Plan(s *pb.Scene) []*pb.Task { return Round(s, 1) }

// Round returns the tasks of progressive round r (from 1) for s in plan order, with Index
// (from 0 within the round), Phase, Round and spec set and nothing else (the store fills in
// ids and states, and renumbers appended rounds). s must have passed scene.Validate.
func Round(s *pb.Scene, r uint32) []*pb.Task {
	p := plan{round: r}
	p.emit(s)
	if len(p.tasks) > 0 {
		p.add(&pb.Task{Phase: pb.Phase_PHASE_BUILD, Spec: &pb.Task_BuildPhotonMap{BuildPhotonMap: &pb.BuildPhotonMapSpec{}}})
		if n := PrecomputeShards(s); n > 0 {
			for range n {
				p.add(&pb.Task{Phase: pb.Phase_PHASE_PRECOMPUTE, Spec: &pb.Task_PrecomputeIrradiance{PrecomputeIrradiance: &pb.PrecomputeIrradianceSpec{
					RadiusScale: RadiusScale(scene.Alpha(s), p.round),
				}}})
			}
			p.add(&pb.Task{Phase: pb.Phase_PHASE_MERGE, Spec: &pb.Task_MergeIrradiance{MergeIrradiance: &pb.MergeIrradianceSpec{}}})
		}
	}
	p.tiles(s)
	p.add(&pb.Task{Phase: pb.Phase_PHASE_COMPOSITE, Spec: &pb.Task_Composite{Composite: &pb.CompositeSpec{}}})
	return p.tasks
}

// PrecomputeShards returns how many irradiance precompute tasks a round of s has: one per
// global emission shard with final gathering, none without a global map or in PHOTON_MAP
// mode.
func PrecomputeShards(s *pb.Scene) int {
	if !scene.FinalGather(s) {
		return 0
	}
	for _, m := range scene.PhotonMaps(s) {
		if m.Kind == pb.PhotonMapKind_PHOTON_MAP_KIND_GLOBAL {
			return int(scene.ShardsPerMap(s, m.Photons))
		}
	}
	return 0
}

// PhotonsPerRound returns the photon paths one round emits, all maps together.
func PhotonsPerRound(s *pb.Scene) uint64 {
	var n uint64
	for _, m := range scene.PhotonMaps(s) {
		n += m.Photons
	}
	return n
}

// RadiusScale is progressive photon mapping's shrinking of the search radii in round r
// (from 1): sqrt(prod over i in [1, r) of (i + alpha) / (i + 1)), 1 in the first round.
func RadiusScale(alpha float64, r uint32) float64 {
	prod := 1.0
	for i := uint32(1); i < r; i++ {
		prod *= (float64(i) + alpha) / float64(i+1)
	}
	return math.Sqrt(prod)
}

type plan struct {
	round uint32
	tasks []*pb.Task
}

// add appends t (phase and spec set) with the next index and the plan's round.
func (p *plan) add(t *pb.Task) {
	t.Index = uint32(len(p.tasks))
	t.Round = p.round
	p.tasks = append(p.tasks, t)
}

func (p *plan) emit(s *pb.Scene) {
	per := scene.PhotonsPerShard(s)
	for _, m := range scene.PhotonMaps(s) {
		base := uint64(p.round-1) * m.Photons
		for first := uint64(0); first < m.Photons; first += per {
			p.add(&pb.Task{Phase: pb.Phase_PHASE_EMIT, Spec: &pb.Task_EmitPhotons{EmitPhotons: &pb.EmitPhotonsSpec{
				Map: m.Kind, FirstPhoton: base + first, PhotonCount: min(per, m.Photons-first), TotalPhotons: m.Photons,
			}}})
		}
	}
}

func (p *plan) tiles(s *pb.Scene) {
	w, h := s.GetFilm().GetWidth(), s.GetFilm().GetHeight()
	tile := scene.TileSize(s)
	firstSample := (p.round - 1) * scene.SamplesPerPixel(s)
	scale := RadiusScale(scene.Alpha(s), p.round)
	for y := uint32(0); y < h; y += tile {
		for x := uint32(0); x < w; x += tile {
			p.add(&pb.Task{Phase: pb.Phase_PHASE_RENDER, Spec: &pb.Task_RenderTile{RenderTile: &pb.RenderTileSpec{
				Rect:        &pb.PixelRect{X: x, Y: y, Width: min(tile, w-x), Height: min(tile, h-y)},
				RadiusScale: scale, FirstSample: firstSample,
			}}})
		}
	}
}

// PhaseCounts returns the tasks per phase of tasks, in order.
func PhaseCounts(tasks []*pb.Task) []*pb.PhaseProgress {
	var out []*pb.PhaseProgress
	for _, t := range tasks {
		if n := len(out); n == 0 || out[n-1].Phase != t.GetPhase() {
			out = append(out, &pb.PhaseProgress{Phase: t.GetPhase()})
		}
		out[len(out)-1].TasksTotal++
	}
	return out
}
