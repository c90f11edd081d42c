package importer

import (
	"fmt"
	"math"
	"path/filepath"
	"strings"

	pb "photonfarm/proto/renderfarm/v1"
)

// build is what an import gathers, whatever the format: the scene so far, what it
// skipped and chose, the model's bounds, its camera and whether anything emits.
type build struct {
	scene  *pb.Scene
	res    *Result
	bounds box
	camera *pb.Camera
	// aspect is the camera's width / height, 0 when the model does not say.
	aspect float64
	emits  bool
}

func newBuild(src string) *build {
	return &build{scene: &pb.Scene{Name: truncate(strings.TrimSuffix(filepath.Base(src), filepath.Ext(src)))}, res: &Result{}}
}

func (b *build) skip(format string, args ...any) {
	b.res.Skipped = append(b.res.Skipped, fmt.Sprintf(format, args...))
}

func (b *build) chose(format string, args ...any) {
	b.res.Chose = append(b.res.Chose, fmt.Sprintf(format, args...))
}

// finish fills in what the model did not say: a film, a camera framing the model, the
// environment the options name, else a sky when nothing lights it; and returns the result.
func (b *build) finish(w *writer, opt Options) (*Result, error) {
	if opt.Environment != "" {
		if err := b.environment(w, opt.Environment); err != nil {
			return nil, err
		}
	}
	aspect := b.aspect
	if aspect <= 0 {
		aspect = 4.0 / 3
	}
	h := opt.Height
	if h == 0 {
		h = uint32(math.Max(1, math.Round(float64(opt.Width)/aspect)))
	}
	b.scene.Film = &pb.Film{Width: opt.Width, Height: h}
	if b.camera == nil {
		b.camera = frame(b.bounds)
		b.chose("a camera framing the model from the front and above (the model has no perspective camera)")
	}
	b.scene.Camera = b.camera
	if len(b.scene.Lights) == 0 && !b.emits && b.scene.Environment == nil {
		b.scene.Environment = &pb.Environment{Radiance: color(1, 1, 1)}
		b.chose("a white sky (the model has no light)")
	}
	b.res.Scene = b.scene
	return b.res, nil
}

// frame is a camera that sees the whole box: from the front (+Z) and a little above, at
// a distance at which a 40-degree view holds the box's bounding sphere.
func frame(bx box) *pb.Camera {
	if !bx.full {
		bx = box{min: [3]float64{-1, -1, -1}, max: [3]float64{1, 1, 1}, full: true}
	}
	var c [3]float64
	r := 0.0
	for i := range c {
		c[i] = (bx.min[i] + bx.max[i]) / 2
		r += (bx.max[i] - bx.min[i]) * (bx.max[i] - bx.min[i]) / 4
	}
	r = math.Max(math.Sqrt(r), 1e-6)
	const fov = 40.0
	d := r / math.Sin(fov/2*math.Pi/180)
	dir := normalize([3]float64{0, 0.35, 1})
	return &pb.Camera{
		Position:           vec([3]float64{c[0] + d*dir[0], c[1] + d*dir[1], c[2] + d*dir[2]}),
		LookAt:             vec(c),
		Up:                 vec([3]float64{0, 1, 0}),
		VerticalFovDegrees: fov,
	}
}
