package limits

import (
	"testing"
	"time"

	"google.golang.org/protobuf/proto"

	"photonfarm/contract/rules"
	"photonfarm/contract/scene/scenetest"
	"photonfarm/contract/tasks"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

// TestCompositeAtTheTileCapCompletes renders the most tiles a round may have
// (max_tiles_per_round: 2048x2048 in 8-pixel tiles; reduced: 128x128, 256 tiles) on two
// workers and logs how big the composite's lease was against the message limit.
func TestCompositeAtTheTileCapCompletes(t *testing.T) {
	side := size(uint32(2048), uint32(128))
	r := newRun(t)
	r.f.StartWorker(t, "--threads", "1")
	sc := scenetest.Unlit(side, side)
	sc.Film.TileSize = 8
	job := r.render(sc, 2*time.Hour)
	all := r.f.Tasks(t, job.GetId())
	tiles := farmtest.TasksOf(all, pb.Phase_PHASE_RENDER)
	composite := farmtest.TasksOf(all, pb.Phase_PHASE_COMPOSITE)[0]
	// The lease the composite's worker got: its task with the round's tiles filled in.
	spec := &pb.CompositeSpec{}
	for _, tile := range tiles {
		spec.Tiles = append(spec.Tiles, &pb.TileInput{Rect: tile.GetRenderTile().GetRect(),
			Tile: tasks.Find(tile.GetOutputs(), pb.ArtifactKind_ARTIFACT_KIND_TILE_EXR)})
	}
	leased := proto.Clone(composite).(*pb.Task)
	leased.Spec = &pb.Task_Composite{Composite: spec}
	n, limit := proto.Size(&pb.LeaseTaskResponse{Task: leased, SceneDigest: job.GetSceneDigest(), Lease: &pb.Lease{TaskId: composite.GetId(), Epoch: 1}}),
		int(rules.RPC.GetMaxMessageBytes())
	t.Logf("%d tiles: the composite's lease is %d bytes (%.1f a tile), %.1f%% of the %d-byte message limit",
		len(tiles), n, float64(n)/float64(len(tiles)), 100*float64(n)/float64(limit), limit)
	if len(tiles) != int(side/8)*int(side/8) || n > limit/4 {
		t.Errorf("%d tiles, lease of %d bytes: want %d tiles and a lease under a quarter of the limit", len(tiles), n, (side/8)*(side/8))
	}
	r.taskTimes()
}
