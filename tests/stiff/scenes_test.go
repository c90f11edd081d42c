package stiff

// Scene builders. The Cornell-like box is scenes/cornell-box.json (read with the client's
// scene-file reader, so there is one copy of its geometry), then scaled, moved and
// shrunk to a tiny film; the other scenes are built here from a few primitives.

import (
	"context"
	"math"
	"path/filepath"
	"sync"
	"testing"

	"google.golang.org/protobuf/proto"

	"photonfarm/client"
	"photonfarm/contract/assets"
	"photonfarm/contract/assets/assetstest"
	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

func v3(x, y, z float64) *pb.Vec3   { return &pb.Vec3{X: x, Y: y, Z: z} }
func grey(c float64) *pb.Color      { return &pb.Color{R: c, G: c, B: c} }
func rgb(r, g, b float64) *pb.Color { return &pb.Color{R: r, G: g, B: b} }
func lambert(name string, rho *pb.Color) *pb.Material {
	return &pb.Material{Name: name, Kind: &pb.Material_Lambert{Lambert: &pb.Lambert{Reflectance: rho}}}
}
func emissive(name string, le *pb.Color) *pb.Material {
	return &pb.Material{Name: name, Kind: &pb.Material_Emissive{Emissive: &pb.Emissive{Radiance: le}}}
}
func glass(name string, ior float64) *pb.Material {
	return &pb.Material{Name: name, Kind: &pb.Material_Dielectric{Dielectric: &pb.Dielectric{Ior: ior}}}
}
func sphere(name, material string, c *pb.Vec3, r float64) *pb.Shape {
	return &pb.Shape{Name: name, Material: material, Geometry: &pb.Shape_Sphere{Sphere: &pb.Sphere{Center: c, Radius: r}}}
}
func quad(name, material string, o, u, v *pb.Vec3) *pb.Shape {
	return &pb.Shape{Name: name, Material: material, Geometry: &pb.Shape_Quad{Quad: &pb.Quad{Origin: o, EdgeU: u, EdgeV: v}}}
}
func triangles(name, material string, positions []*pb.Vec3, indices []uint32) *pb.Shape {
	return &pb.Shape{Name: name, Material: material, Geometry: &pb.Shape_Triangles{Triangles: &pb.TriangleMesh{Positions: positions, Indices: indices}}}
}

// tiny sets the film to w x h in 16-pixel tiles, 4 samples per pixel, 8 light samples and
// small photon maps (20,000 paths each, in shards of 10,000): about a second a case.
func tiny(sc *pb.Scene, w, h uint32) *pb.Scene {
	sc.Film = &pb.Film{Width: w, Height: h, TileSize: 16}
	sc.Sampling = &pb.Sampling{SamplesPerPixel: 4, Seed: 7, LightSamples: 8}
	sc.Photons = &pb.PhotonMapping{GlobalPhotons: 20000, CausticPhotons: 20000, PhotonsPerShard: 10000}
	return sc
}

var (
	cornellOnce sync.Once
	cornell     *pb.Scene
	cornellErr  error
)

// cornellMM is scenes/cornell-box.json as it is (millimetres, the box about 556 across,
// the camera outside its open front), on a 24x24 film.
func cornellMM(t *testing.T) *pb.Scene {
	t.Helper()
	cornellOnce.Do(func() {
		var sf *client.SceneFile
		sf, cornellErr = client.ReadSceneFile(context.Background(), filepath.Join(farmtest.RepoRoot(), "scenes", "cornell-box.json"))
		if cornellErr == nil {
			cornell = sf.Scene
		}
	})
	if cornellErr != nil {
		t.Fatal(cornellErr)
	}
	return tiny(proto.Clone(cornell).(*pb.Scene), 24, 24)
}

// cornellBox is the Cornell box scaled so that it is `size` units across, then moved by
// offset; lights keep their radiance, so the image should not change at all.
func cornellBox(t *testing.T, size float64, offset *pb.Vec3) *pb.Scene {
	sc := cornellMM(t)
	transform(sc, size/cornellSize, offset)
	return sc
}

// cornellSize is the Cornell box's width in its own unit (millimetres).
const cornellSize = 556.0

// transform scales every position and length of sc by s about the origin, then moves it
// by offset (nil: no move). Radiances and intensities are left alone: point and sun lights
// are not used with it.
func transform(sc *pb.Scene, s float64, offset *pb.Vec3) {
	if offset == nil {
		offset = v3(0, 0, 0)
	}
	pt := func(p *pb.Vec3) *pb.Vec3 {
		return v3(p.GetX()*s+offset.X, p.GetY()*s+offset.Y, p.GetZ()*s+offset.Z)
	}
	vec := func(p *pb.Vec3) *pb.Vec3 { return v3(p.GetX()*s, p.GetY()*s, p.GetZ()*s) }
	sc.Camera.Position = pt(sc.Camera.Position)
	sc.Camera.LookAt = pt(sc.Camera.LookAt)
	for _, sh := range sc.Shapes {
		switch g := sh.Geometry.(type) {
		case *pb.Shape_Sphere:
			g.Sphere.Center = pt(g.Sphere.Center)
			g.Sphere.Radius *= s
		case *pb.Shape_Quad:
			g.Quad.Origin = pt(g.Quad.Origin)
			g.Quad.EdgeU = vec(g.Quad.EdgeU)
			g.Quad.EdgeV = vec(g.Quad.EdgeV)
		case *pb.Shape_Triangles:
			for i, p := range g.Triangles.Positions {
				g.Triangles.Positions[i] = pt(p)
			}
		}
	}
	for _, l := range sc.Lights {
		if p := l.GetPoint(); p != nil {
			p.Position = pt(p.Position)
		}
	}
}

// without returns sc with the named shapes removed.
func without(sc *pb.Scene, names ...string) *pb.Scene {
	var kept []*pb.Shape
	for _, sh := range sc.Shapes {
		drop := false
		for _, n := range names {
			drop = drop || sh.Name == n
		}
		if !drop {
			kept = append(kept, sh)
		}
	}
	sc.Shapes = kept
	return sc
}

// The Cornell box's quad light: 130 x 105 mm of radiance cornellLe.
var cornellLe = [3]float64{18.387, 13.9873, 6.75357}

const cornellLightArea = 130.0 * 105.0

// sphereLitCornell is the Cornell box (millimetres) with its quad light replaced by a
// sphere light of radius r hanging 100 mm under the ceiling, with the quad light's power:
// a sphere of radiance L emits pi L 4 pi r^2, a one-sided quad pi L A.
func sphereLitCornell(t *testing.T, r float64) *pb.Scene {
	sc := without(cornellMM(t), "light")
	k := cornellLightArea / (4 * math.Pi * r * r)
	for _, m := range sc.Materials {
		if m.Name == "light" {
			m.Kind = &pb.Material_Emissive{Emissive: &pb.Emissive{Radiance: rgb(cornellLe[0]*k, cornellLe[1]*k, cornellLe[2]*k)}}
		}
	}
	sc.Shapes = append(sc.Shapes, sphere("light", "light", v3(278, 448.8, 280), r))
	return sc
}

// glassInCornell adds a glass ball of the given index of refraction on the Cornell box's
// floor, in front of the blocks, where the camera sees it and the light falls on it.
func glassInCornell(t *testing.T, ior float64) *pb.Scene {
	sc := cornellMM(t)
	sc.Materials = append(sc.Materials, glass("glass", ior))
	sc.Shapes = append(sc.Shapes, sphere("ball", "glass", v3(370, 100, 120), 100))
	return sc
}

// insideCornell puts the camera inside the Cornell box, looking at the back wall; the
// box's open front is closed with a white wall behind the camera, so every camera ray
// meets a surface.
func insideCornell(t *testing.T) *pb.Scene {
	sc := cornellMM(t)
	sc.Camera = &pb.Camera{Position: v3(278, 273, 60), LookAt: v3(278, 273, 559), Up: v3(0, 1, 0), VerticalFovDegrees: 70}
	sc.Shapes = append(sc.Shapes, quad("front-wall", "white", v3(0, 0, -1), v3(0, 548.8, 0), v3(556, 0, 0)))
	return sc
}

// fog is a homogeneous medium of single-scattering albedo `albedo` in every channel,
// density (sigma_t) `density` per scene unit and Henyey-Greenstein asymmetry g.
func fog(albedo, density, g float64) *pb.Medium {
	return &pb.Medium{Coefficients: &pb.Medium_Albedo{Albedo: &pb.MediumAlbedo{Albedo: grey(albedo), Density: density}}, G: g}
}

// smokeGrid is a farm grid file of 12^3 cells over the unit cube, densities 0.2 + 1.6
// (x / 11) sin(pi (y + 0.5) / 12) by cell (from 0.2 to 1.8 across x, peaking mid-height).
func smokeGrid() [][]byte {
	const n = 12
	g := &assets.GridData{Nx: n, Ny: n, Nz: n, Max: [3]float32{1, 1, 1}}
	for range n {
		for y := range n {
			for x := range n {
				g.Densities = append(g.Densities, float32(0.2+1.6*float64(x)/(n-1)*math.Sin(math.Pi*(float64(y)+0.5)/n)))
			}
		}
	}
	return [][]byte{assetstest.EncodedGrid(g)}
}

// gridSmoke is the medium of albedo 1 and Henyey-Greenstein asymmetry g whose densities
// are smokeGrid's.
func gridSmoke(g float64) *pb.Medium {
	return &pb.Medium{G: g, Coefficients: &pb.Medium_Grid{Grid: &pb.MediumGrid{
		Path: "smoke.farmgrid", Digest: rules.DigestOf(smokeGrid()[0]), Albedo: grey(1), DensityScale: 1}}}
}

// withBlobs is c with the blobs its scene names.
func withBlobs(c stiffCase, blobs func() [][]byte) stiffCase {
	c.blobs = blobs
	return c
}

// absorbing is a medium that absorbs sigmaA per channel and per scene unit and scatters
// nothing (albedo 0).
func absorbing(sigmaA *pb.Color) *pb.Medium {
	return &pb.Medium{Coefficients: &pb.Medium_Sigma{Sigma: &pb.MediumCoefficients{SigmaA: sigmaA, SigmaS: grey(0)}}}
}

// sigmaT is a medium's extinction sigma_a + sigma_s per channel.
func sigmaT(m *pb.Medium) [3]float64 {
	if a := m.GetAlbedo(); a != nil {
		return [3]float64{a.GetDensity(), a.GetDensity(), a.GetDensity()}
	}
	sa, ss := m.GetSigma().GetSigmaA(), m.GetSigma().GetSigmaS()
	return [3]float64{sa.GetR() + ss.GetR(), sa.GetG() + ss.GetG(), sa.GetB() + ss.GetB()}
}

// inwardCube is the inside of the cube [0, s]^3: six quads of the material, facing in.
func inwardCube(material string, s float64) []*pb.Shape {
	x, y, z := v3(s, 0, 0), v3(0, s, 0), v3(0, 0, s)
	return []*pb.Shape{
		quad("floor", material, v3(0, 0, 0), z, x),   // y = 0, facing +y
		quad("ceiling", material, v3(0, s, 0), x, z), // y = s, facing -y
		quad("left", material, v3(0, 0, 0), y, z),    // x = 0, facing +x
		quad("right", material, v3(s, 0, 0), z, y),   // x = s, facing -x
		quad("near", material, v3(0, 0, 0), x, y),    // z = 0, facing +z
		quad("far", material, v3(0, 0, s), y, x),     // z = s, facing -z
	}
}

// glowingLe is the radiance every wall of the glowing cube emits.
const glowingLe = 1.0

// glowingCube is the inside of a closed cube s units across whose walls all emit
// glowingLe and reflect nothing, filled with the scene's medium m (nil: vacuum; the
// medium's ball bounds the cube, so all of its inside is in the medium), seen from the
// centre by a camera looking at the middle of the far wall (z = s) with a 90-degree field
// of view on a square film: every pixel sees the far wall, at distances from s/2 (the
// image centre) to s sqrt(3)/2 (its corners). 300,000 volume photon paths in 3 shards and
// the volume estimate over k = 200, as worker/render/volume_furnace_test.cpp measured
// within 1% for an optical depth of 1 across (a uniform field needs no detail); 20,000
// global and caustic paths (the walls reflect nothing).
func glowingCube(s float64, m *pb.Medium) *pb.Scene {
	c := s / 2
	sc := &pb.Scene{
		Camera:    &pb.Camera{Position: v3(c, c, c), LookAt: v3(c, c, s), Up: v3(0, 1, 0), VerticalFovDegrees: 90},
		Materials: []*pb.Material{emissive("glow", grey(glowingLe))},
		Shapes:    inwardCube("glow", s),
		Medium:    m,
	}
	tiny(sc, 16, 16)
	sc.Photons = &pb.PhotonMapping{GlobalPhotons: 20000, CausticPhotons: 20000, VolumePhotons: 300000, PhotonsPerShard: 100000,
		VolumeEstimate: &pb.RadianceEstimate{Neighbours: 200}}
	return sc
}

// withSamples gives a scene n camera samples per pixel.
func withSamples(n uint32) func(sc *pb.Scene) {
	return func(sc *pb.Scene) { sc.Sampling.SamplesPerPixel = n }
}

// withLamp hangs a sphere light of the walls' radiance (radius 0.1, in view in front of
// the far wall) in the unit glowing cube sc: a light inside the medium.
func withLamp(sc *pb.Scene) {
	sc.Materials = append(sc.Materials, emissive("lamp", grey(glowingLe)))
	sc.Shapes = append(sc.Shapes, sphere("lamp", "lamp", v3(0.6, 0.55, 0.75), 0.1))
}

// withMurkyBall puts a ball of glass (index 1.5, radius 0.25, at the centre of the unit
// glowing cube sc) filled with an albedo-1 medium of density 4 (optical depth 2 across)
// in front of the camera, which moves back to 0.08 from the near wall: the ball's
// silhouette (36.5 degrees from the view axis) is in view, where camera rays meet the
// glass at grazing angles, and light scattered inside meets the glass beyond the critical
// angle (41.8 degrees) and is trapped by total internal reflection until it scatters
// again.
func withMurkyBall(sc *pb.Scene) {
	sc.Camera.Position = v3(0.5, 0.5, 0.08)
	sc.Materials = append(sc.Materials, glass("glass", 1.5))
	ball := sphere("murky-ball", "glass", v3(0.5, 0.5, 0.5), 0.25)
	ball.InteriorMedium = fog(1, 4, 0)
	sc.Shapes = append(sc.Shapes, ball)
}

// foggyCornell is the closed Cornell box (millimetres) with the camera inside it
// (insideCornell), filled with fog m: the camera and the box's light are both in the
// medium. 20,000 volume photon paths, as many as the other maps.
func foggyCornell(t *testing.T, m *pb.Medium) *pb.Scene {
	sc := insideCornell(t)
	sc.Medium = m
	sc.Photons.VolumePhotons = 20000
	return sc
}

// furnace is the white furnace: the inside of a closed Lambert sphere of radius 1 and
// albedo rho, lit by a point light of intensity 1 at its centre, seen by a camera at the
// centre. Every wall point's radiance is L = rho Phi / (pi A (1 - rho)) with Phi = 4 pi I
// and A = 4 pi R^2, since every pair of points on a sphere's inside exchanges light with
// the same form factor.
func furnace(rho float64, photons uint64, neighbours uint32) *pb.Scene {
	sc := &pb.Scene{
		Camera:    &pb.Camera{Position: v3(0, 0, 0), LookAt: v3(0, 0, 1), Up: v3(0, 1, 0), VerticalFovDegrees: 90},
		Materials: []*pb.Material{lambert("wall", grey(rho))},
		Shapes:    []*pb.Shape{sphere("furnace", "wall", v3(0, 0, 0), 1)},
		Lights:    []*pb.Light{{Name: "centre", Kind: &pb.Light_Point{Point: &pb.PointLight{Position: v3(0, 0, 0), Intensity: grey(1)}}}},
	}
	tiny(sc, 16, 16)
	sc.Sampling.SamplesPerPixel = 4
	sc.Photons = &pb.PhotonMapping{
		GlobalPhotons:   photons,
		PhotonsPerShard: photons / 4,
		GlobalEstimate:  &pb.RadianceEstimate{Neighbours: neighbours},
	}
	return sc
}

// furnaceRadiance is the analytic answer for furnace(rho, ...) with I = 1 and R = 1.
func furnaceRadiance(rho float64) float64 {
	phi := 4 * math.Pi * 1.0
	area := 4 * math.Pi * 1.0
	return rho * phi / (math.Pi * area * (1 - rho))
}

// grazingPlane is a large Lambert floor (albedo rho, 2000 units square) under a sun
// elevation degrees above the horizon, seen by a camera 1 unit above it looking 1.15
// degrees down with a 1.5 degree field of view: every camera ray meets the floor between
// about 0.4 and 1.9 degrees, every shadow ray leaves it at `elevation` degrees. Nothing
// else is there, so a floor pixel's radiance is exactly rho E sin(elevation) / pi.
func grazingPlane(rho, irradiance, elevation float64) *pb.Scene {
	e := elevation * math.Pi / 180
	sc := &pb.Scene{
		Camera:    &pb.Camera{Position: v3(0, 1, -50), LookAt: v3(0, 0, 0), Up: v3(0, 1, 0), VerticalFovDegrees: 1.5},
		Materials: []*pb.Material{lambert("floor", grey(rho))},
		Shapes:    []*pb.Shape{quad("floor", "floor", v3(-1000, 0, -1000), v3(0, 0, 2000), v3(2000, 0, 0))},
		Lights: []*pb.Light{{Name: "low-sun", Kind: &pb.Light_Sun{Sun: &pb.SunLight{
			Direction: v3(0.3*math.Cos(e), -math.Sin(e), math.Cos(e)), Irradiance: grey(irradiance)}}}},
	}
	return tiny(sc, 24, 24)
}

// grazingRadiance is the analytic floor radiance of grazingPlane.
func grazingRadiance(rho, irradiance, elevation float64) float64 {
	e := elevation * math.Pi / 180
	d := math.Sqrt(0.09*math.Cos(e)*math.Cos(e) + math.Sin(e)*math.Sin(e) + math.Cos(e)*math.Cos(e))
	return rho * irradiance * (math.Sin(e) / d) / math.Pi
}

// degenerateJunk is a mesh of triangles with no area: all three corners equal, two
// corners repeated, three collinear corners (along an axis and along a diagonal), and a
// zero-length edge far from the others; placed in the middle of the Cornell box.
func degenerateJunk(name, material string) *pb.Shape {
	p := []*pb.Vec3{
		v3(200, 200, 200), // 0
		v3(300, 250, 250), // 1
		v3(250, 300, 300), // 2
		v3(350, 200, 200), // 3: collinear with 0 along x
		v3(400, 200, 200), // 4
		v3(250, 250, 250), // 5: diagonal 0-5-6
		v3(300, 300, 300), // 6
	}
	idx := []uint32{
		0, 0, 0, // one point
		1, 1, 2, // repeated corner
		2, 1, 2, // repeated corner, other order
		0, 3, 4, // collinear along x
		0, 5, 6, // collinear along the diagonal
		6, 5, 0, // the same, reversed
	}
	return triangles(name, material, p, idx)
}

// straddlingFurnace is a closed Lambert sphere (radius 1, albedo 0.8) lit only by an
// emissive quad that pokes through its wall: the quad's origin and one edge lie outside,
// the rest inside, facing +y. With decoy, a tiny unlit diffuse ball outside the sphere
// keeps any planner heuristic about a lone sphere from applying. The search radius is
// fixed so that the decoy does not change it.
func straddlingFurnace(decoy bool) *pb.Scene {
	sc := &pb.Scene{
		Camera:    &pb.Camera{Position: v3(0, 0, 0), LookAt: v3(0, 0, 1), Up: v3(0, 1, 0), VerticalFovDegrees: 90},
		Materials: []*pb.Material{lambert("wall", grey(0.8)), emissive("panel", grey(1))},
		Shapes: []*pb.Shape{
			sphere("furnace", "wall", v3(0, 0, 0), 1),
			quad("panel", "panel", v3(-0.1, -0.1, 1.2), v3(0.2, 0, 0), v3(0, 0, -1)),
		},
	}
	if decoy {
		sc.Shapes = append(sc.Shapes, sphere("decoy", "wall", v3(10, 10, 10), 0.01))
	}
	tiny(sc, 16, 16)
	sc.Photons = &pb.PhotonMapping{GlobalPhotons: 40000, PhotonsPerShard: 20000,
		GlobalEstimate: &pb.RadianceEstimate{MaxRadius: 0.15}}
	return sc
}
