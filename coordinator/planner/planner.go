// Package planner splits a validated scene into the tasks of a job, phase by phase:
//
//   - emit: photon-emission shards of PhotonMapping.photons_per_shard paths (the last one
//     partial), first for the global map (if any shape reflects diffusely), then for the
//     caustic map (only if some shape is specular: mirror, dielectric, conductor);
//   - build: one task merging the shards into a kd-tree snapshot (only if there are shards);
//   - render: one RENDER_TILE task per tile, row-major, the last row and column partial;
//   - composite: one COMPOSITE task.
//
// Planning is deterministic: the same scene always gives the same plan.
package planner

import (
	"photonfarm/coordinator/scene"
	pb "photonfarm/proto/renderfarm/v1"
)

// Plan returns the tasks of a job for s in plan order, with Index, Phase and spec set and
// nothing else (the store fills in ids and states). s must have passed scene.Validate.
func Plan(s *pb.Scene) []*pb.Task {
	var p plan
	p.emit(s)
	if len(p.tasks) > 0 {
		p.add(&pb.Task{Phase: pb.Phase_PHASE_BUILD, Spec: &pb.Task_BuildPhotonMap{BuildPhotonMap: &pb.BuildPhotonMapSpec{}}})
	}
	p.tiles(s)
	p.add(&pb.Task{Phase: pb.Phase_PHASE_COMPOSITE, Spec: &pb.Task_Composite{Composite: &pb.CompositeSpec{}}})
	return p.tasks
}

// Maps returns the photon maps a scene gets, in plan order, with their photon path counts.
func Maps(s *pb.Scene) []MapPlan {
	surf := scene.SurfacesOf(s)
	var maps []MapPlan
	if surf.Diffuse {
		maps = append(maps, MapPlan{Kind: pb.PhotonMapKind_PHOTON_MAP_KIND_GLOBAL, Photons: scene.GlobalPhotons(s)})
	}
	if surf.Specular {
		maps = append(maps, MapPlan{Kind: pb.PhotonMapKind_PHOTON_MAP_KIND_CAUSTIC, Photons: scene.CausticPhotons(s)})
	}
	return maps
}

// MapPlan is one photon map of a job: its kind and the photon paths emitted for it.
type MapPlan struct {
	Kind    pb.PhotonMapKind
	Photons uint64
}

type plan struct{ tasks []*pb.Task }

// add appends t (phase and spec set) with the next index.
func (p *plan) add(t *pb.Task) {
	t.Index = uint32(len(p.tasks))
	p.tasks = append(p.tasks, t)
}

func (p *plan) emit(s *pb.Scene) {
	per := scene.PhotonsPerShard(s)
	for _, m := range Maps(s) {
		for first := uint64(0); first < m.Photons; first += per {
			p.add(&pb.Task{Phase: pb.Phase_PHASE_EMIT, Spec: &pb.Task_EmitPhotons{EmitPhotons: &pb.EmitPhotonsSpec{
				Map: m.Kind, FirstPhoton: first, PhotonCount: min(per, m.Photons-first), TotalPhotons: m.Photons,
			}}})
		}
	}
}

func (p *plan) tiles(s *pb.Scene) {
	w, h := s.GetFilm().GetWidth(), s.GetFilm().GetHeight()
	tile := scene.TileSize(s)
	for y := uint32(0); y < h; y += tile {
		for x := uint32(0); x < w; x += tile {
			p.add(&pb.Task{Phase: pb.Phase_PHASE_RENDER, Spec: &pb.Task_RenderTile{RenderTile: &pb.RenderTileSpec{Rect: &pb.PixelRect{
				X: x, Y: y, Width: min(tile, w-x), Height: min(tile, h-y),
			}}}})
		}
	}
}
