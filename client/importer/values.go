package importer

import (
	"bytes"
	"context"
	"fmt"
	"io"
	"math"
	"strconv"

	"photonfarm/contract/assets"
	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

func color(r, g, b float64) *pb.Color { return &pb.Color{R: r, G: g, B: b} }

func vec(v [3]float64) *pb.Vec3 { return &pb.Vec3{X: v[0], Y: v[1], Z: v[2]} }

func clamp01(v float64) float64 {
	if math.IsNaN(v) {
		return 0
	}
	return math.Min(math.Max(v, 0), 1)
}

// truncate keeps a name from a model short enough for the farm's names.
func truncate(s string) string { return rules.Truncate(s, 200) }

// checkImage checks image bytes as the coordinator will (contract/assets.CheckTexture).
func checkImage(data []byte) (assets.Texture, error) {
	open := func() (io.ReadCloser, error) { return io.NopCloser(bytes.NewReader(data)), nil }
	return assets.CheckTexture(context.Background(), open, assets.SceneLimits().MaxBytes, assets.MaxTexturePixels())
}

// parseNumber reads a decimal number of an MTL file, finite.
func parseNumber(b []byte) (float64, error) {
	v, err := strconv.ParseFloat(string(b), 64)
	if err != nil || math.IsNaN(v) || math.IsInf(v, 0) {
		return 0, fmt.Errorf("%q is not a finite number", rules.Truncate(string(b), 40))
	}
	return v, nil
}
