package service_test

import (
	"testing"

	"google.golang.org/grpc/codes"

	"photonfarm/contract/scene/scenetest"
	pb "photonfarm/proto/renderfarm/v1"
)

// TestTooManyTasksAreRefusedAtSubmitAndPlan: issue 12's task explosion, a 604-byte scene of
// a 16384² film in 8-pixel tiles (4,194,304 tiles), issue 17's million-task job (the same
// film in 16-pixel tiles, 1,048,576 tiles), and a photon map of 50,000 shards are refused by
// SubmitJob and by PlanScene before anything is planned, with a message naming the limit and
// the fields that make the count; nothing is stored. A round at the limits plans.
func TestTooManyTasksAreRefusedAtSubmitAndPlan(t *testing.T) {
	tests := []struct {
		name    string
		scene   func() *pb.Scene
		field   string
		message string
	}{
		{"16384² film in 8-pixel tiles", func() *pb.Scene {
			s := scenetest.Valid(16384, 16384)
			s.Film.TileSize = 8
			return s
		}, "film.tile_size", "film.tile_size: 8-pixel tiles (film.tile_size) make 4194304 tiles of a 16384x16384 film (film.width x film.height) per round, more than max_tiles_per_round, 65536: use larger tiles or a smaller film"},
		{"16384² film in 16-pixel tiles: a million tasks", func() *pb.Scene {
			s := scenetest.Valid(16384, 16384)
			s.Film.TileSize = 16
			return s
		}, "film.tile_size", "film.tile_size: 16-pixel tiles (film.tile_size) make 1048576 tiles of a 16384x16384 film (film.width x film.height) per round, more than max_tiles_per_round, 65536: use larger tiles or a smaller film"},
		{"50,000 shards of the global map", func() *pb.Scene {
			s := scenetest.Valid(32, 32)
			s.Photons = &pb.PhotonMapping{GlobalPhotons: 50_000_000, PhotonsPerShard: 1000}
			return s
		}, "photons.photons_per_shard", "photons.photons_per_shard: 1000 photons per shard (photons.photons_per_shard) make 50000 emission shards of the global map's 50000000 photons (photons.global_photons) per round, more than max_shards_per_map, 10000: use more photons per shard"},
	}
	f := newFarm(t)
	for _, tt := range tests {
		t.Run(tt.name, func(t *testing.T) {
			_, err := f.jobs.SubmitJob(f.ctx, &pb.SubmitJobRequest{Scene: tt.scene()})
			wantCode(t, "SubmitJob", err, codes.InvalidArgument, tt.field)
			if !containsMessage(err, tt.message) {
				t.Errorf("SubmitJob: %v, want %q", err, tt.message)
			}
			_, err = f.jobs.PlanScene(f.ctx, &pb.PlanSceneRequest{Scene: tt.scene()})
			wantCode(t, "PlanScene", err, codes.InvalidArgument, tt.field)
			if !containsMessage(err, tt.message) {
				t.Errorf("PlanScene: %v, want %q", err, tt.message)
			}
		})
	}
	if list, err := f.jobs.ListJobs(f.ctx, &pb.ListJobsRequest{}); err != nil || len(list.Jobs) != 0 {
		t.Errorf("ListJobs after the refusals = %v, %v; want no jobs", list, err)
	}

	atLimit := scenetest.Unlit(2048, 2048) // within max_film_pixels
	atLimit.Film.TileSize = 8
	plan, err := f.jobs.PlanScene(f.ctx, &pb.PlanSceneRequest{Scene: atLimit})
	if err != nil {
		t.Fatalf("PlanScene of 65,536 tiles (the limit): %v", err)
	}
	render := uint32(0)
	for _, p := range plan.Phases {
		if p.Phase == pb.Phase_PHASE_RENDER {
			render = p.TasksTotal
		}
	}
	if render != 65536 {
		t.Errorf("PlanScene of a 2048² film in 8-pixel tiles: %d render tasks, want 65536 (phases %v)", render, plan.Phases)
	}
}
