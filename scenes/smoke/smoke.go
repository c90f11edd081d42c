// Package smoke makes the grid-medium demonstration scene (issue 15): a plume of smoke
// rising from the floor of a room corner, lit low by the sun and by a blue sky, its density
// a farm grid file (docs/grid-format.md) this package computes, so that no large binary is
// committed. `go run ./scenes/smoke/gen -o DIR` writes DIR/smoke.json and DIR/plume.farmgrid.
package smoke

import (
	"bytes"
	"fmt"
	"math"
	"os"
	"path/filepath"

	"google.golang.org/protobuf/encoding/protojson"

	"photonfarm/contract/assets"
	pb "photonfarm/proto/renderfarm/v1"
)

// The plume's cells: taller than wide, 1.2 M cells (4.7 MB).
const (
	nx, ny, nz = 80, 160, 80
	gridFile   = "plume.farmgrid"
)

// Plume is the plume's densities over the box [0, 1] x [0, 2] x [0, 1]: a column rising
// from a source near the floor, widening and thinning as it rises, drifting sideways, with
// turbulent detail from a few octaves of value noise; 0 at the box's faces.
func Plume() *assets.GridData {
	g := &assets.GridData{Nx: nx, Ny: ny, Nz: nz, Max: [3]float32{1, 2, 1}}
	g.Densities = make([]float32, nx*ny*nz)
	for k := range nz {
		for j := range ny {
			for i := range nx {
				x, y, z := (float64(i)+0.5)/nx, 2*(float64(j)+0.5)/ny, (float64(k)+0.5)/nz
				g.Densities[(k*ny+j)*nx+i] = float32(density(x, y, z))
			}
		}
	}
	return g
}

// density of the plume at (x, y, z) in its box.
func density(x, y, z float64) float64 {
	h := y / 2 // 0 at the floor, 1 at the top
	// The column's axis drifts and sways as it rises; its radius grows.
	cx := 0.5 + 0.18*h*h + 0.04*math.Sin(7*h)
	cz := 0.5 + 0.05*math.Sin(5*h+1)
	radius := 0.07 + 0.3*h
	turbulence := fbm(3*x, 3*y, 3*z) // in about [-1, 1]
	r := math.Hypot(x-cx, z-cz) / radius
	r += 0.35 * turbulence
	if r >= 1 {
		return 0
	}
	core := 1 - r*r
	d := core * core * (0.55 + 0.45*fbm(6*x+11, 6*y, 6*z+5)) // wisps
	d *= smoothstep(0, 0.08, h) * (1 - smoothstep(0.75, 1, h))
	// Clear of the box's faces, so the placed box leaves no edge.
	for _, v := range []float64{x, z} {
		d *= smoothstep(0, 0.06, v) * smoothstep(0, 0.06, 1-v)
	}
	return math.Max(0, d)
}

func smoothstep(a, b, v float64) float64 {
	t := math.Min(1, math.Max(0, (v-a)/(b-a)))
	return t * t * (3 - 2*t)
}

// fbm is four octaves of value noise, in about [-1, 1].
func fbm(x, y, z float64) float64 {
	sum, amp := 0.0, 0.5
	for range 4 {
		sum += amp * valueNoise(x, y, z)
		x, y, z, amp = 2*x+17.3, 2*y+5.1, 2*z+9.7, amp/2
	}
	return sum / 0.9375
}

// valueNoise is smooth noise in [-1, 1]: random values at integer points, blended by
// smoothsteps.
func valueNoise(x, y, z float64) float64 {
	x0, y0, z0 := math.Floor(x), math.Floor(y), math.Floor(z)
	fx, fy, fz := fade(x-x0), fade(y-y0), fade(z-z0)
	at := func(dx, dy, dz float64) float64 { return lattice(int64(x0+dx), int64(y0+dy), int64(z0+dz)) }
	lerp := func(a, b, t float64) float64 { return a + (b-a)*t }
	return lerp(
		lerp(lerp(at(0, 0, 0), at(1, 0, 0), fx), lerp(at(0, 1, 0), at(1, 1, 0), fx), fy),
		lerp(lerp(at(0, 0, 1), at(1, 0, 1), fx), lerp(at(0, 1, 1), at(1, 1, 1), fx), fy), fz)
}

func fade(t float64) float64 { return t * t * (3 - 2*t) }

// lattice is a random value in [-1, 1] for an integer point (a 64-bit hash of it).
func lattice(x, y, z int64) float64 {
	h := uint64(x)*0x9e3779b97f4a7c15 ^ uint64(y)*0xc2b2ae3d27d4eb4f ^ uint64(z)*0x165667b19e3779f9
	h ^= h >> 31
	h *= 0x7fb5d329728ea185
	h ^= h >> 27
	return float64(h>>11)/float64(1<<53)*2 - 1
}

// Scene is the demonstration scene, naming the plume's grid file by path.
func Scene() *pb.Scene {
	v := func(x, y, z float64) *pb.Vec3 { return &pb.Vec3{X: x, Y: y, Z: z} }
	rgb := func(r, g, b float64) *pb.Color { return &pb.Color{R: r, G: g, B: b} }
	lambert := func(name string, c *pb.Color) *pb.Material {
		return &pb.Material{Name: name, Kind: &pb.Material_Lambert{Lambert: &pb.Lambert{Reflectance: c}}}
	}
	return &pb.Scene{
		Name:     "smoke",
		Camera:   &pb.Camera{Position: v(0.2, 1.3, 5.2), LookAt: v(0, 1.25, 0), Up: v(0, 1, 0), VerticalFovDegrees: 40},
		Film:     &pb.Film{Width: 320, Height: 240, TileSize: 32},
		Sampling: &pb.Sampling{SamplesPerPixel: 16, Seed: 1},
		Materials: []*pb.Material{
			lambert("floor", rgb(0.42, 0.36, 0.3)),
			lambert("wall", rgb(0.4, 0.42, 0.45)),
		},
		Shapes: []*pb.Shape{
			{Name: "floor", Material: "floor", Geometry: &pb.Shape_Quad{Quad: &pb.Quad{Origin: v(-5, 0, 4), EdgeU: v(10, 0, 0), EdgeV: v(0, 0, -6)}}},
			{Name: "back wall", Material: "wall", Geometry: &pb.Shape_Quad{Quad: &pb.Quad{Origin: v(-5, 0, -2), EdgeU: v(10, 0, 0), EdgeV: v(0, 4, 0)}}},
		},
		Lights: []*pb.Light{
			{Name: "sun", Kind: &pb.Light_Sun{Sun: &pb.SunLight{Direction: v(-1, -0.5, -0.15), Irradiance: rgb(4.2, 3.7, 3), AngularDiameterDegrees: 0.53}}},
		},
		Environment: &pb.Environment{Radiance: rgb(0.06, 0.08, 0.13)},
		Photons:     &pb.PhotonMapping{GlobalPhotons: 100000, VolumePhotons: 300000},
		Medium: &pb.Medium{
			Coefficients: &pb.Medium_Grid{Grid: &pb.MediumGrid{
				Path: gridFile, Albedo: rgb(0.92, 0.92, 0.92), DensityScale: 25,
				// The plume's box [0, 1] x [0, 2] x [0, 1], 1.3 m wide and 2.6 m tall, centred
				// over the floor in front of the wall.
				Transform: &pb.Transform{Scale: v(1.3, 1.3, 1.3), Translation: v(-0.75, 0, -0.65)},
			}},
			G: 0.35,
		},
	}
}

// Write writes smoke.json and plume.farmgrid into dir.
func Write(dir string) error {
	if err := os.MkdirAll(dir, 0o755); err != nil {
		return err
	}
	var grid bytes.Buffer
	if err := assets.EncodeFarmGrid(&grid, Plume()); err != nil {
		return err
	}
	if err := os.WriteFile(filepath.Join(dir, gridFile), grid.Bytes(), 0o644); err != nil {
		return err
	}
	scene, err := protojson.MarshalOptions{Multiline: true, Indent: "  "}.Marshal(Scene())
	if err != nil {
		return fmt.Errorf("smoke: %w", err)
	}
	return os.WriteFile(filepath.Join(dir, "smoke.json"), append(scene, '\n'), 0o644)
}
