package service_test

import (
	"math"
	"strings"
	"testing"

	"google.golang.org/protobuf/proto"

	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

// The composite's lease lists every tile of its round: at the most tiles a round may have,
// with every field at its widest, it must fit the message limit with room to spare.
func TestCompositeLeaseOfTheMostTilesFitsTheMessageLimit(t *testing.T) {
	n := int(rules.Scene.GetMaxTilesPerRound())
	digest := "sha256:" + strings.Repeat("f", 64)
	spec := &pb.CompositeSpec{
		PreviousAccumulation: &pb.Artifact{Name: "accumulation.exr", Digest: digest, SizeBytes: math.MaxInt64},
		Reference:            &pb.Artifact{Name: "reference.exr", Digest: digest, SizeBytes: math.MaxInt64},
	}
	for range n {
		spec.Tiles = append(spec.Tiles, &pb.TileInput{
			Rect: &pb.PixelRect{X: 16383, Y: 16383, Width: 256, Height: 256},
			Tile: &pb.Artifact{Name: "tile.exr", Digest: digest, SizeBytes: math.MaxInt64},
		})
	}
	resp := &pb.LeaseTaskResponse{
		Lease:       &pb.Lease{TaskId: strings.Repeat("j", 128), Epoch: math.MaxUint64},
		Task:        &pb.Task{Id: strings.Repeat("j", 128), JobId: strings.Repeat("j", 128), Index: math.MaxUint32, Round: 1000, Spec: &pb.Task_Composite{Composite: spec}},
		SceneDigest: digest,
	}
	size, limit := proto.Size(resp), int(rules.RPC.GetMaxMessageBytes())
	t.Logf("%d tiles: %d bytes, %.1f a tile, %.1f%% of the %d-byte limit", n, size, float64(size)/float64(n), 100*float64(size)/float64(limit), limit)
	if size > limit/4 {
		t.Errorf("the composite's lease of %d tiles is %d bytes, over a quarter of the %d-byte limit", n, size, limit)
	}
}
