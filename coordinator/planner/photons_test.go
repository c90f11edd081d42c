package planner_test

import (
	"fmt"
	"strings"
	"testing"

	"google.golang.org/protobuf/proto"

	"photonfarm/contract/rules"
	"photonfarm/contract/scene"
	"photonfarm/contract/scene/scenetest"
	"photonfarm/coordinator/planner"
	pb "photonfarm/proto/renderfarm/v1"
)

// withoutPhotons checks that tasks are indexed in order and returns those of the render
// and composite phases.
func withoutPhotons(t *testing.T, tasks []*pb.Task) []*pb.Task {
	t.Helper()
	var out []*pb.Task
	for i, task := range tasks {
		if task.Index != uint32(i) {
			t.Fatalf("task %d has index %d", i, task.Index)
		}
		if task.Phase == pb.Phase_PHASE_RENDER || task.Phase == pb.Phase_PHASE_COMPOSITE {
			out = append(out, task)
		}
	}
	return out
}

func material(name string, kind string) *pb.Material {
	m := &pb.Material{Name: name}
	switch kind {
	case "mirror":
		m.Kind = &pb.Material_Mirror{Mirror: &pb.Mirror{Reflectance: &pb.Color{R: 1, G: 1, B: 1}}}
	case "glass":
		m.Kind = &pb.Material_Dielectric{Dielectric: &pb.Dielectric{Ior: 1.5}}
	case "gold":
		m.Kind = &pb.Material_Conductor{Conductor: &pb.Conductor{Eta: &pb.Color{R: 0.1, G: 0.4, B: 1.4}, K: &pb.Color{R: 4, G: 2.4, B: 1.6}}}
	}
	return m
}

// shape sets the materials of shapes 0 (ball) and 1 (floor) of scenetest.Valid.
func shapes(ball, floor string) func(*pb.Scene) {
	return func(s *pb.Scene) {
		s.Materials = append(s.Materials, material("mirror", "mirror"), material("glass", "glass"), material("gold", "gold"))
		s.Shapes[0].Material, s.Shapes[1].Material = ball, floor
	}
}

// describe is a compact plan: "G0+1000/2500 ... B R R C" with emit shards as
// map+first+count/total.
func describe(tasks []*pb.Task) string {
	var parts []string
	for _, t := range tasks {
		switch t.Phase {
		case pb.Phase_PHASE_EMIT:
			e := t.GetEmitPhotons()
			parts = append(parts, fmt.Sprintf("%c%d+%d/%d", strings.TrimPrefix(e.Map.String(), "PHOTON_MAP_KIND_")[0],
				e.FirstPhoton, e.PhotonCount, e.TotalPhotons))
		case pb.Phase_PHASE_BUILD:
			if t.GetBuildPhotonMap() == nil {
				parts = append(parts, "B?")
			} else {
				parts = append(parts, "B")
			}
		case pb.Phase_PHASE_RENDER:
			parts = append(parts, "R")
		case pb.Phase_PHASE_COMPOSITE:
			parts = append(parts, "C")
		}
	}
	return strings.Join(parts, " ")
}

func TestPlanPhotonPhases(t *testing.T) {
	photons := func(global, caustic, per uint64) func(*pb.Scene) {
		return func(s *pb.Scene) {
			s.Photons = &pb.PhotonMapping{GlobalPhotons: global, CausticPhotons: caustic, PhotonsPerShard: per}
		}
	}
	volumePhotons := func(n uint64) func(*pb.Scene) { return func(s *pb.Scene) { s.Photons.VolumePhotons = n } }
	both := func(fs ...func(*pb.Scene)) func(*pb.Scene) {
		return func(s *pb.Scene) {
			for _, f := range fs {
				f(s)
			}
		}
	}
	tests := []struct {
		name   string
		mutate func(*pb.Scene)
		want   string
	}{
		{"diffuse only: defaults, global map only", func(*pb.Scene) {},
			"G0+100000/200000 G100000+100000/200000 B R C"},
		{"last shard partial", photons(2500, 0, 1000),
			"G0+1000/2500 G1000+1000/2500 G2000+500/2500 B R C"},
		{"one shard holds the whole map", photons(1000, 0, 5000), "G0+1000/1000 B R C"},
		{"mirror adds the caustic map after the global one", both(shapes("mirror", "white"), photons(2000, 3000, 1000)),
			"G0+1000/2000 G1000+1000/2000 C0+1000/3000 C1000+1000/3000 C2000+1000/3000 B R C"},
		{"glass", both(shapes("glass", "white"), photons(1000, 1000, 1000)), "G0+1000/1000 C0+1000/1000 B R C"},
		{"conductor", both(shapes("gold", "white"), photons(1000, 1000, 1000)), "G0+1000/1000 C0+1000/1000 B R C"},
		{"specular only: caustic map only", both(shapes("glass", "gold"), photons(1000, 2000, 1000)),
			"C0+1000/2000 C1000+1000/2000 B R C"},
		{"no reflecting surface: no photons at all", shapes("light", "light"), "R C"},
		{"scattering fog adds the volume map after the others", both(shapes("mirror", "white"), photons(1000, 1000, 1000), volumePhotons(2500), scatteringFog),
			"G0+1000/1000 C0+1000/1000 V0+1000/2500 V1000+1000/2500 V2000+500/2500 B R C"},
		{"absorbing fog: no volume map", both(photons(1000, 0, 1000), volumePhotons(2500), absorbingFog), "G0+1000/1000 B R C"},
		{"fog over a specular-only scene: volume map without precompute", both(shapes("glass", "gold"), photons(1000, 1000, 1000), volumePhotons(1000), scatteringFog),
			"C0+1000/1000 V0+1000/1000 B R C"},
	}
	for _, tt := range tests {
		t.Run(tt.name, func(t *testing.T) {
			s := scenetest.Valid(32, 32) // one tile
			tt.mutate(s)
			if err := scene.Validate(s); err != nil {
				t.Fatal(err)
			}
			tasks := planner.Plan(s)
			if got := describe(tasks); got != tt.want {
				t.Errorf("plan = %s\nwant   %s", got, tt.want)
			}
			withoutPhotons(t, tasks) // checks the indices
		})
	}
}

// TestPlanLargestRoundStaysWithinLimits plans the largest round Validate accepts: the most
// tiles (max_tiles_per_round) and, for all three maps, the most emission shards
// (max_shards_per_map); one tile or one shard more is refused. Planning cost is bounded by
// these two limits (docs/limits.md).
func TestPlanLargestRoundStaysWithinLimits(t *testing.T) {
	maxTiles, maxShards := rules.Scene.GetMaxTilesPerRound(), rules.Scene.GetMaxShardsPerMap()
	perShard := uint64(rules.Min(&pb.PhotonMapping{}, "photons_per_shard"))
	s := scenetest.Valid(2048, 2048) // 4,194,304 pixels: at 8 pixels a tile, the most tiles
	s.Film.TileSize = 8
	shapes("mirror", "white")(s)
	scatteringFog(s)
	s.Photons = &pb.PhotonMapping{GlobalPhotons: maxShards * perShard, CausticPhotons: maxShards * perShard, VolumePhotons: maxShards * perShard, PhotonsPerShard: perShard}
	if err := scene.Validate(s); err != nil {
		t.Fatal(err)
	}
	if got := scene.TilesPerRound(s); got != maxTiles {
		t.Fatalf("%d tiles, want the limit %d (choose another film)", got, maxTiles)
	}
	tasks := planner.Plan(s)
	counts := map[pb.Phase]uint64{}
	var photons uint64
	for _, task := range tasks {
		counts[task.Phase]++
		photons += task.GetEmitPhotons().GetPhotonCount()
	}
	want := map[pb.Phase]uint64{pb.Phase_PHASE_EMIT: 3 * maxShards, pb.Phase_PHASE_BUILD: 1, pb.Phase_PHASE_PRECOMPUTE: maxShards,
		pb.Phase_PHASE_MERGE: 1, pb.Phase_PHASE_RENDER: maxTiles, pb.Phase_PHASE_COMPOSITE: 1}
	if fmt.Sprint(counts) != fmt.Sprint(want) || photons != 3*maxShards*perShard {
		t.Errorf("tasks per phase %v covering %d photons, want %v covering %d", counts, photons, want, 3*maxShards*perShard)
	}

	for _, tt := range []struct {
		name   string
		mutate func(*pb.Scene)
		field  string
	}{
		{"one global photon more", func(s *pb.Scene) { s.Photons.GlobalPhotons++ }, "photons.photons_per_shard"},
		{"one caustic photon more", func(s *pb.Scene) { s.Photons.CausticPhotons++ }, "photons.photons_per_shard"},
		{"one volume photon more", func(s *pb.Scene) { s.Photons.VolumePhotons++ }, "photons.photons_per_shard"},
		{"smaller tiles", func(s *pb.Scene) { s.Film.TileSize-- }, "film.tile_size"},
	} {
		over := proto.Clone(s).(*pb.Scene)
		tt.mutate(over)
		if err, ok := scene.Validate(over).(*scene.FieldError); !ok || err.Field != tt.field {
			t.Errorf("%s: Validate = %v, want an error at %s", tt.name, err, tt.field)
		}
	}
}
