// Package planner splits a validated scene into the tasks of a job: the render phase (one
// RENDER_TILE task per tile, row-major, the last row and column partial) followed by the
// composite phase (one COMPOSITE task). Planning is deterministic: the same scene always
// gives the same plan.
package planner

import (
	"photonfarm/coordinator/scene"
	pb "photonfarm/proto/renderfarm/v1"
)

// Plan returns the tasks of a job for s in plan order, with Index, Phase and spec set and
// nothing else (the store fills in ids and states). s must have passed scene.Validate.
func Plan(s *pb.Scene) []*pb.Task {
	w, h := s.GetFilm().GetWidth(), s.GetFilm().GetHeight()
	tile := scene.TileSize(s)
	var tasks []*pb.Task
	for y := uint32(0); y < h; y += tile {
		for x := uint32(0); x < w; x += tile {
			tasks = append(tasks, &pb.Task{
				Index: uint32(len(tasks)),
				Phase: pb.Phase_PHASE_RENDER,
				Spec: &pb.Task_RenderTile{RenderTile: &pb.RenderTileSpec{Rect: &pb.PixelRect{
					X: x, Y: y, Width: min(tile, w-x), Height: min(tile, h-y),
				}}},
			})
		}
	}
	tasks = append(tasks, &pb.Task{
		Index: uint32(len(tasks)),
		Phase: pb.Phase_PHASE_COMPOSITE,
		Spec:  &pb.Task_Composite{Composite: &pb.CompositeSpec{}},
	})
	return tasks
}
