package limits

import (
	"strings"
	"testing"
	"time"

	"photonfarm/contract/rules"
	"photonfarm/contract/scene/scenetest"
	pb "photonfarm/proto/renderfarm/v1"
)

// furnace is the inside of a closed Lambert sphere of albedo 0.8 around a point light:
// every path stores about 0.8 / (1 - 0.8) = 4 photons (one at each diffuse bounce after
// the first), so paths photon paths fill a snapshot of about 4 · paths photons. A small
// ball outside keeps the global map in the plan (a lone sphere's surface cannot light
// itself, the planner's heuristic says); a few gather rays and neighbours keep the
// irradiance precompute over every stored photon short.
func furnace(paths uint64) *pb.Scene {
	sc := scenetest.Valid(16, 16)
	sc.Camera = &pb.Camera{Position: scenetest.V(0, 0, 0), LookAt: scenetest.V(0, 0, 1), Up: scenetest.V(0, 1, 0), VerticalFovDegrees: 90}
	sc.Film.TileSize = 16
	sc.Materials = []*pb.Material{{Name: "wall", Kind: &pb.Material_Lambert{Lambert: &pb.Lambert{Reflectance: &pb.Color{R: 0.8, G: 0.8, B: 0.8}}}}}
	sc.Shapes = []*pb.Shape{
		{Name: "furnace", Material: "wall", Geometry: &pb.Shape_Sphere{Sphere: &pb.Sphere{Center: scenetest.V(0, 0, 0), Radius: 1}}},
		{Name: "outside", Material: "wall", Geometry: &pb.Shape_Sphere{Sphere: &pb.Sphere{Center: scenetest.V(5, 0, 0), Radius: 0.1}}},
	}
	sc.Lights = []*pb.Light{{Name: "centre", Kind: &pb.Light_Point{Point: &pb.PointLight{Position: scenetest.V(0, 0, 0), Intensity: &pb.Color{R: 1, G: 1, B: 1}}}}}
	sc.Photons = &pb.PhotonMapping{GlobalPhotons: paths, PhotonsPerShard: 100_000, GlobalEstimate: &pb.RadianceEstimate{Neighbours: 8}}
	sc.Indirect = &pb.Indirect{GatherRays: 4, SecondaryGatherRays: 1}
	return sc
}

// TestSnapshotAtThePhotonCapRenders renders a furnace whose snapshot holds nearly the most
// photons a snapshot may (max_snapshot_photons, all global, with irradiance: the largest
// snapshot there is; reduced: 100,000 paths) and logs the builder's memory. With
// -limits.full, a furnace over the cap must fail as bad input saying what to lower.
func TestSnapshotAtThePhotonCapRenders(t *testing.T) {
	limit := rules.Scene.GetMaxSnapshotPhotons()
	paths := size(limit/4*39/40, uint64(100_000)) // 2.5% under, about 60 standard deviations
	r := newRun(t)
	job := r.render(furnace(paths), time.Hour)
	var photons uint64
	for _, task := range r.f.Tasks(t, job.GetId()) {
		if task.GetPhase() == pb.Phase_PHASE_BUILD || task.GetPhase() == pb.Phase_PHASE_MERGE {
			a := task.GetOutputs()[0]
			t.Logf("  %s snapshot: %d bytes (%s)", task.GetPhase(), a.GetSizeBytes(), mb(uint64(a.GetSizeBytes())))
			if task.GetPhase() == pb.Phase_PHASE_BUILD {
				photons = (uint64(a.GetSizeBytes()) - 128) / 20 // one map: header, directory entry, 20 bytes a photon
			}
		}
	}
	peak := r.f.Coordinator().PeakRSS(t)
	t.Logf("%d paths stored %d photons (cap %d); coordinator peak %s, %.0f MB a million photons", paths, photons, limit, mb(peak), float64(peak)/float64(photons))
	if photons > limit {
		t.Errorf("%d photons stored, over the cap %d: choose fewer paths", photons, limit)
	}
	r.taskTimes()
	if !*full {
		return
	}
	over := r.f.Submit(t, furnace(limit/4*41/40))
	ended, err := r.f.Client.Watch(ctx(t, time.Hour), over.GetId(), nil)
	if err != nil {
		t.Fatal(err)
	}
	want := "more than the 32000000 photons a snapshot may hold (scene_limits.max_snapshot_photons)"
	if ended.GetState() != pb.JobState_JOB_STATE_FAILED || ended.GetFailureKind() != pb.FailureKind_FAILURE_KIND_BAD_INPUT ||
		!strings.Contains(ended.GetError(), want) || !strings.Contains(ended.GetError(), "lower photons.global_photons") {
		t.Errorf("a furnace over the cap: %v %v %q, want it failed as bad input naming the limit", ended.GetState(), ended.GetFailureKind(), ended.GetError())
	}
	t.Logf("over the cap: %s; coordinator peak since start %s", ended.GetError(), mb(r.f.Coordinator().PeakRSS(t)))
}
