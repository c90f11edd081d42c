package planner_test

import (
	"testing"

	"google.golang.org/protobuf/proto"

	"photonfarm/contract/scene/scenetest"
	"photonfarm/coordinator/planner"
	pb "photonfarm/proto/renderfarm/v1"
)

type rect struct{ x, y, w, h uint32 }

func TestPlan(t *testing.T) {
	tests := []struct {
		name        string
		w, h, tile  uint32
		wantTiles   []rect // nil: only check the count
		wantNumTile int
	}{
		{"one pixel", 1, 1, 0, []rect{{0, 0, 1, 1}}, 1},
		{"exact default tiles", 64, 32, 0, []rect{{0, 0, 32, 32}, {32, 0, 32, 32}}, 2},
		{"partial last row and column", 40, 20, 16, []rect{
			{0, 0, 16, 16}, {16, 0, 16, 16}, {32, 0, 8, 16},
			{0, 16, 16, 4}, {16, 16, 16, 4}, {32, 16, 8, 4},
		}, 6},
		{"tile bigger than image", 10, 300, 256, []rect{{0, 0, 10, 256}, {0, 256, 10, 44}}, 2},
		{"large", 1920, 1080, 0, nil, 60 * 34},
	}
	for _, tt := range tests {
		t.Run(tt.name, func(t *testing.T) {
			s := scenetest.Valid(tt.w, tt.h)
			s.Film.TileSize = tt.tile
			tasks := withoutPhotons(t, planner.Plan(s))
			if len(tasks) != tt.wantNumTile+1 {
				t.Fatalf("got %d tasks, want %d tiles and a composite", len(tasks), tt.wantNumTile)
			}
			var covered uint64
			for i, task := range tasks[:len(tasks)-1] {
				r := task.GetRenderTile().GetRect()
				if task.Phase != pb.Phase_PHASE_RENDER || r == nil {
					t.Fatalf("task %d = %v, want a render tile with index %d", i, task, i)
				}
				if tt.wantTiles != nil && (rect{r.X, r.Y, r.Width, r.Height}) != tt.wantTiles[i] {
					t.Errorf("tile %d = %v, want %v", i, r, tt.wantTiles[i])
				}
				covered += uint64(r.Width) * uint64(r.Height)
			}
			if covered != uint64(tt.w)*uint64(tt.h) {
				t.Errorf("tiles cover %d pixels, want %d", covered, tt.w*tt.h)
			}
			last := tasks[len(tasks)-1]
			if last.Phase != pb.Phase_PHASE_COMPOSITE || last.GetComposite() == nil {
				t.Errorf("last task = %v, want the composite", last)
			}
		})
	}
}

func TestPlanIsDeterministic(t *testing.T) {
	s := scenetest.Valid(100, 70)
	a, b := planner.Plan(s), planner.Plan(s)
	for i := range a {
		if !proto.Equal(a[i], b[i]) {
			t.Fatalf("task %d differs: %v vs %v", i, a[i], b[i])
		}
	}
}
