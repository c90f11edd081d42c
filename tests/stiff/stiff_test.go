package stiff

import (
	"context"
	"fmt"
	"math"
	"strconv"
	"strings"
	"testing"
	"time"

	pb "photonfarm/proto/renderfarm/v1"
)

// stiffCase is one stiff or extreme scene. Every case's image must be free of NaN and
// infinity in every channel, no camera sample of its job may have come out NaN or infinite
// (farm.render), and no pixel of the beauty or of a light-carrying layer (direct,
// indirect, caustic, volume) may exceed bound, per colour: by default the radiance of the
// brightest emitter the scene uses, over one minus its reflectance (a surface cannot
// reflect more radiance than the brightest source sends it; an emitter that reflects adds
// what it reflects to what it emits: brightestEmitter); cases lit by point or sun lights, or seen from inside glass,
// state their own. check then asserts what the case pins down.
type stiffCase struct {
	name    string
	scene   func(t *testing.T) *pb.Scene
	timeout time.Duration // for the render; 0 means 60 s
	heavy   bool          // only with -stiff.heavy
	// bound, if not nil, replaces the brightest emitter's radiance as the energy bound,
	// with why saying where it comes from.
	bound func(sc *pb.Scene) ([3]float64, string)
	check func(t *testing.T, f *farm, name string, sc *pb.Scene, r *rendered)
	// blobs, if not nil, are the files the scene names by digest (a grid medium's),
	// uploaded before it is submitted.
	blobs func() [][]byte
}

// cornellRef is the Cornell box (millimetres) as cornellMM gives it, rendered once.
func cornellRef(t *testing.T, f *farm) *rendered {
	return reference(t, f, "cornell-mm", func() *pb.Scene { return cornellMM(t) })
}

// pinpointCase lights the box with a sphere light of radius fraction of the box and the
// quad light's power, and compares it with a 5%-radius sphere light of the same power.
func pinpointCase(name string, fraction float64) stiffCase {
	return stiffCase{
		name:  name,
		scene: func(t *testing.T) *pb.Scene { return sphereLitCornell(t, fraction*cornellSize) },
		check: func(t *testing.T, f *farm, name string, sc *pb.Scene, r *rendered) {
			big := reference(t, f, "cornell-sphere-light-5pc", func() *pb.Scene { return sphereLitCornell(t, 0.05*cornellSize) })
			bigLe := brightestEmitter(sphereLitCornell(t, 0.05*cornellSize))
			for k, col := range beauty {
				checkClose(t, name, col, "image average of direct+indirect+caustic (vs a 5%-radius light of equal power)",
					meanReflected(r.img, k), meanReflected(big.img, k), 0.03)
			}
			checkBoundReflected(t, name, r.img, bigLe, "radiance of a 5%-radius sphere light of equal power")
		},
	}
}

var cases = []stiffCase{
	// Scale: radiance does not depend on the unit, so the box 1e-4 or 1e5 units across
	// must give the image of the box 1 unit across (same seed, same samples).
	{
		name:  "scale-1e-4-units-matches-scale-1",
		scene: func(t *testing.T) *pb.Scene { return cornellBox(t, 1e-4, nil) },
		check: func(t *testing.T, f *farm, name string, sc *pb.Scene, r *rendered) {
			ref := reference(t, f, "cornell-size-1", func() *pb.Scene { return cornellBox(t, 1, nil) })
			checkMeansClose(t, name, r.img, ref.img, beauty, 0.01, "the box 1 unit across")
			checkPixelsClose(t, name, r.img, ref.img, "R", 0.05, 0.005, 0.02, "the box 1 unit across")
		},
	},
	{
		name:  "scale-1e5-units-matches-scale-1",
		scene: func(t *testing.T) *pb.Scene { return cornellBox(t, 1e5, nil) },
		check: func(t *testing.T, f *farm, name string, sc *pb.Scene, r *rendered) {
			ref := reference(t, f, "cornell-size-1", func() *pb.Scene { return cornellBox(t, 1, nil) })
			checkMeansClose(t, name, r.img, ref.img, beauty, 0.01, "the box 1 unit across")
			checkPixelsClose(t, name, r.img, ref.img, "R", 0.05, 0.005, 0.02, "the box 1 unit across")
		},
	},
	// A pin-point light: a sphere light of radius 1e-3 of the box with the power of the
	// box's quad light (radiance ~4e6) lights the walls as a 5%-radius sphere of the same
	// power does; and no wall reflects more than that large sphere's radiance (a spike from
	// the tiny light's sampling would).
	pinpointCase("pinpoint-sphere-light-1e-3-keeps-power", 1e-3),
	// Smaller still: radius 1e-5 of the box (radiance ~4e10), where the cone of directions
	// towards the light is so narrow that 1 - cos(theta_max) underflows a float unless
	// computed with care.
	pinpointCase("pinpoint-sphere-light-1e-5-keeps-power", 1e-5),
	// Glass of index 1.0001 bends and reflects (Fresnel ~2.5e-9) almost nothing: the
	// image is the box without the ball.
	{
		name:  "glass-ior-1.0001-is-nearly-invisible",
		scene: func(t *testing.T) *pb.Scene { return glassInCornell(t, 1.0001) },
		check: func(t *testing.T, f *farm, name string, sc *pb.Scene, r *rendered) {
			ref := cornellRef(t, f)
			checkMeansClose(t, name, r.img, ref.img, beauty, 0.02, "the box without the ball")
		},
	},
	// Glass of index 4: strong reflection, total internal reflection beyond 14.5 degrees.
	// Glass absorbs nothing, so the image average stays within a broad band of the box's.
	{
		name:  "glass-ior-4-finite-and-bounded",
		scene: func(t *testing.T) *pb.Scene { return glassInCornell(t, 4) },
		check: func(t *testing.T, f *farm, name string, sc *pb.Scene, r *rendered) {
			ref := cornellRef(t, f)
			for _, ch := range beauty {
				got, want := mean(t, name, r.img, ch, nil), mean(t, name, ref.img, ch, nil)
				if !(got > 0.5*want && got < 1.5*want) {
					t.Errorf("case %s: channel %s: image average %.6g, want within [0.5, 1.5] x the box without the ball (%.6g)", name, ch, got, want)
				}
			}
		},
	},
	// Grazing incidence: a floor under a sun 0.5 degrees above the horizon, seen at 0.4 to
	// 1.9 degrees. Every pixel is rho E sin(elevation) / pi exactly: a shadow ray that
	// re-hits the floor (acne) makes a dark pixel, a lost one a black pixel.
	{
		name:  "grazing-sun-and-camera-floor-radiance-exact",
		scene: func(t *testing.T) *pb.Scene { return grazingPlane(0.8, 100, 0.5) },
		bound: func(sc *pb.Scene) ([3]float64, string) {
			l := grazingRadiance(0.8, 100, 0.5) * 1.01
			return [3]float64{l, l, l}, "the analytic floor radiance + 1%"
		},
		check: func(t *testing.T, f *farm, name string, sc *pb.Scene, r *rendered) {
			want := grazingRadiance(0.8, 100, 0.5)
			checkEveryPixel(t, name, r.img, "R", want, 0.01, "the analytic floor radiance rho E sin(elevation) / pi")
			checkClose(t, name, "R", "image average", mean(t, name, r.img, "R", nil), want, 0.005)
			checkClose(t, name, "A", "image average (every ray meets the floor)", mean(t, name, r.img, "A", nil), 1, 1e-6)
		},
	},
	// The same with every pixel supersampled (anti-aliasing FULL, 12 samples): averaging
	// supersamples must not gain or lose energy.
	{
		name: "grazing-floor-with-full-supersampling-still-exact",
		scene: func(t *testing.T) *pb.Scene {
			s := grazingPlane(0.8, 100, 0.5)
			s.Antialiasing = &pb.Antialiasing{Mode: pb.AntialiasingMode_ANTIALIASING_MODE_FULL, EdgeSamples: 12}
			return s
		},
		bound: func(sc *pb.Scene) ([3]float64, string) {
			l := grazingRadiance(0.8, 100, 0.5) * 1.01
			return [3]float64{l, l, l}, "the analytic floor radiance + 1%"
		},
		check: func(t *testing.T, f *farm, name string, sc *pb.Scene, r *rendered) {
			checkEveryPixel(t, name, r.img, "R", grazingRadiance(0.8, 100, 0.5), 0.01, "the analytic floor radiance rho E sin(elevation) / pi")
		},
	},
	// Far from the origin: the Cornell box (millimetres) moved by (1e6, 1e6, 1e6), where a
	// float's spacing is 1/16 mm. Rays leave surfaces with offsets scaled to the
	// coordinates; self-intersection would darken pixels (acne), too big an offset would
	// leak light at the corners.
	{
		name:  "far-from-origin-1e6-no-acne-no-shifted-shadows",
		scene: func(t *testing.T) *pb.Scene { s := cornellMM(t); transform(s, 1, v3(1e6, 1e6, 1e6)); return s },
		check: func(t *testing.T, f *farm, name string, sc *pb.Scene, r *rendered) {
			ref := cornellRef(t, f)
			checkMeansClose(t, name, r.img, ref.img, beauty, 0.02, "the box at the origin")
			checkMeansClose(t, name, r.img, ref.img, []string{"direct.R"}, 0.02, "the box at the origin")
			checkPixelsClose(t, name, r.img, ref.img, "direct.R", 0.2, 0.005, 0.03, "the box at the origin")
		},
	},
	// A camera at the centre of a glass ball (index 1.5): every camera ray leaves the glass
	// at normal incidence, so it sees n^2 T (1 + R + ...) times the radiance outside
	// (T = 0.96, R = 0.04; radiance in a medium of index n is n^2 that in air). Energy
	// bound: n^2 times the light's radiance.
	{
		name:  "camera-at-centre-of-glass-ball-sees-n2-radiance",
		scene: func(t *testing.T) *pb.Scene { return insideGlass(t, 0) },
		bound: glassBound(1.5),
		check: func(t *testing.T, f *farm, name string, sc *pb.Scene, r *rendered) {
			ref := reference(t, f, "inside-cornell", func() *pb.Scene { return insideCornell(t) })
			// n^2 T (L(d) + R L(-d) + R^2 L(d) ...): with L(-d) (the wall behind the
			// camera) between 0 and twice L(d), the ratio is n^2 T (1 + R) within 4.5%.
			n2, rf := 1.5*1.5, 0.04
			for _, ch := range beauty {
				got, out := mean(t, name, r.img, ch, nil), mean(t, name, ref.img, ch, nil)
				checkClose(t, name, ch, "image average / that without the ball", got/out, n2*(1-rf)*(1+rf), 0.05)
			}
		},
	},
	// The camera off centre (0.8 of the radius) in the glass ball: rays beyond the critical
	// angle (41.8 degrees) are trapped by total internal reflection until the path is cut.
	{
		name:  "camera-off-centre-in-glass-ball-total-internal-reflection",
		scene: func(t *testing.T) *pb.Scene { return insideGlass(t, 0.8) },
		bound: glassBound(1.5),
		check: func(t *testing.T, f *farm, name string, sc *pb.Scene, r *rendered) {
			if m := mean(t, name, r.img, "R", nil); !(m > 0) {
				t.Errorf("case %s: channel R: image average %.6g; the room seen through the glass should not be black", name, m)
			}
		},
	},
	// Photon counts: a single photon path, 1M on a tiny image (default), 10M (heavy).
	{
		name:  "one-photon-path-finite",
		scene: func(t *testing.T) *pb.Scene { return fewPhotons(t, 1) },
		bound: fewPhotonsBound,
		check: checkFewPhotons,
	},
	// A hundred paths: a few dozen photons stored, most estimates find fewer than k.
	{
		name:  "hundred-photon-paths-no-spikes",
		scene: func(t *testing.T) *pb.Scene { return fewPhotons(t, 100) },
		bound: fewPhotonsBound,
		check: checkFewPhotons,
	},
	{
		name:    "one-million-photons-tiny-image",
		scene:   func(t *testing.T) *pb.Scene { return manyPhotons(t, 1_000_000) },
		timeout: 90 * time.Second,
		check:   checkManyPhotons(60 * time.Second),
	},
	{
		name:    "ten-million-photons-tiny-image",
		heavy:   true,
		scene:   func(t *testing.T) *pb.Scene { return manyPhotons(t, 10_000_000) },
		timeout: 10 * time.Minute,
		check:   checkManyPhotons(5 * time.Minute),
	},
	// A search radius near zero for both maps: no estimate finds photons (or finds one at
	// a distance of ~1e-9), which must give no light rather than 1/r^2 = 1e18. Direct light
	// does not use photons, so it is unchanged.
	{
		name: "max-radius-1e-9-gives-no-spikes",
		scene: func(t *testing.T) *pb.Scene {
			s := glassInCornell(t, 1.5)
			s.Photons.GlobalEstimate = &pb.RadianceEstimate{MaxRadius: 1e-9}
			s.Photons.CausticEstimate = &pb.RadianceEstimate{MaxRadius: 1e-9}
			return s
		},
		check: func(t *testing.T, f *farm, name string, sc *pb.Scene, r *rendered) {
			ref := reference(t, f, "cornell-glass-1.5", func() *pb.Scene { return glassInCornell(t, 1.5) })
			checkMeansClose(t, name, r.img, ref.img, []string{"direct.R", "direct.G", "direct.B"}, 0.01, "the default radius (direct light uses no photons; edge anti-aliasing may move a few samples)")
			for _, ch := range []string{"indirect.R", "caustic.R"} {
				got, want := mean(t, name, r.img, ch, nil), mean(t, name, ref.img, ch, nil)
				if got > 1.1*want+1e-6 {
					t.Errorf("case %s: channel %s: image average %.6g with max_radius 1e-9, more than with the default radius (%.6g)", name, ch, got, want)
				}
			}
		},
	},
	// A small search radius (5 mm, 1% of the box) over few photons (5,000 paths): most
	// estimates find no photon or one. Dividing what is found by the disc searched is
	// unbiased (the expected estimate is the density, whatever the radius); dividing by the
	// squared distance to the one photon found is not (E[1/r^2] diverges), and a shading
	// point 1 mm from a photon then shows tens of times the light's radiance.
	{
		name: "small-radius-few-photons-estimate-stays-unbiased",
		scene: func(t *testing.T) *pb.Scene {
			s := fewPhotons(t, 5000)
			s.Film = &pb.Film{Width: 32, Height: 32, TileSize: 16}
			s.Photons.GlobalEstimate = &pb.RadianceEstimate{MaxRadius: 5}
			return s
		},
		check: func(t *testing.T, f *farm, name string, sc *pb.Scene, r *rendered) {
			ref := reference(t, f, "cornell-glass-1.5-32px", func() *pb.Scene {
				s := glassInCornell(t, 1.5)
				s.Film = &pb.Film{Width: 32, Height: 32, TileSize: 16}
				return s
			})
			checkMeansClose(t, name, r.img, ref.img, []string{"indirect.R", "indirect.G", "indirect.B"}, 0.2, "20,000 photons and the default radius")
		},
	},
	// Degenerate triangles (a point, repeated corners, collinear corners) in a white mesh
	// and in an emissive mesh: no area, so nothing hits them, no light comes from them, and
	// the image is the box's.
	{
		name: "degenerate-triangles-change-nothing",
		scene: func(t *testing.T) *pb.Scene {
			s := cornellMM(t)
			s.Shapes = append(s.Shapes, degenerateJunk("junk", "white"), degenerateJunk("junk-light", "light"))
			return s
		},
		check: func(t *testing.T, f *farm, name string, sc *pb.Scene, r *rendered) {
			ref := cornellRef(t, f)
			checkMeansClose(t, name, r.img, ref.img, beauty, 0.01, "the box without them")
			checkPixelsClose(t, name, r.img, ref.img, "R", 0.05, 0.005, 0.01, "the box without them")
		},
	},
	// Leaving out what a scene does not need must never leave out what it needs: a sphere
	// lit by a panel that pokes through its wall interreflects inside, so its image must
	// be that of the same scene with an unseen extra diffuse ball (which no planner
	// heuristic about a lone sphere can skip).
	{
		name:  "planner-keeps-global-map-for-a-light-through-the-sphere-wall",
		scene: func(t *testing.T) *pb.Scene { return straddlingFurnace(false) },
		check: func(t *testing.T, f *farm, name string, sc *pb.Scene, r *rendered) {
			ref := reference(t, f, "straddling-furnace-with-decoy", func() *pb.Scene { return straddlingFurnace(true) })
			if m := mean(t, name, ref.img, "indirect.R", nil); !(m > 0) {
				t.Fatalf("case %s: channel indirect.R: the reference (with a decoy) has no indirect light (%.6g)", name, m)
			}
			checkMeansClose(t, name, r.img, ref.img, []string{"indirect.R", "R"}, 0.05, "the same scene with an unseen diffuse ball outside")
		},
	},
	// The white furnace: inside a closed Lambert sphere (rho 0.5 and 0.8) around a point
	// light, every wall point has radiance rho Phi / (pi A (1 - rho)): 1/pi and 4/pi here.
	// With the scene's default indirect mode (final gathering).
	furnaceCase(furnaceSpec{rho: 0.5, paths: 200_000}),
	furnaceCase(furnaceSpec{rho: 0.8, paths: 100_000}),
	// Progressive rounds (fresh photons, shrinking radius) must converge to the same
	// answer: the image is the combination of all rounds.
	furnaceCase(furnaceSpec{rho: 0.8, paths: 40_000, rounds: 3}),
	// Each way of computing indirect light on its own, with a tiny diffuse ball outside the
	// furnace (unlit, unseen) so that the planner's heuristics cannot leave the global map
	// out: whatever the plan, both integrators must conserve energy.
	furnaceCase(furnaceSpec{rho: 0.8, paths: 100_000, mode: pb.IndirectMode_INDIRECT_MODE_FINAL_GATHER, decoy: true}),
	furnaceCase(furnaceSpec{rho: 0.8, paths: 100_000, mode: pb.IndirectMode_INDIRECT_MODE_PHOTON_MAP, decoy: true}),

	// Participating media (docs/media.md, issue 15). The glowing cube (glowingCube): the
	// inside of a closed cube whose walls all emit Le = 1 and reflect nothing, the camera at
	// its centre, in the scene's medium. Filled with a medium of albedo 1, nothing is ever
	// lost and the radiance is Le everywhere in every direction, whatever the density and
	// g: a uniform, isotropic L solves the transport equation there (dL/ds = -sigma_t L +
	// sigma_s integral p L dw = (sigma_s - sigma_t) Le = 0, p integrating to 1) and meets
	// every boundary condition (each wall sends Le). What the medium takes from the wall's
	// light on the way to the camera it must give back, scattered once (from light samples)
	// and more often (from the volume photon map). Density 1: optical depth 0.5 to 0.87
	// from the camera to the far wall.
	// Camera rays that graze a wall (at the image's edges, where walls meet) are where light
	// sampling alone spikes (its estimate goes as 1 / h, h the distance from the ray to the
	// point drawn on the wall); weighed against phase-function samples by MIS, no sample
	// exceeds the wall's radiance (docs/media.md), so every pixel is held to 20%.
	glowingFurnaceCase("media-albedo-1-fog-around-the-camera-keeps-wall-radiance", 1, fog(1, 1, 0), nil),
	// Heterogeneous: the unit cube filled with smoke from a farm grid file whose density
	// varies from 0.2 to 1.8 per unit (smokeGrid), albedo 1: L = Le still, whatever the
	// density's shape (the argument above holds point by point). Optical depth is integrated
	// exactly through the grid's bricks (camera paths, shadow rays), distances drawn by
	// inverting it (single scattering's two strategies, weighed by MIS with those very
	// densities), photons' free flights delta-tracked.
	withBlobs(glowingFurnaceCase("media-albedo-1-grid-smoke-keeps-wall-radiance", 1, gridSmoke(0), nil), smokeGrid),
	// The same smoke scattering forwards (g 0.95, at least path_traced_media_min_abs_g):
	// its multiple scattering path traced, the paths' free flights delta-tracked through
	// the grid.
	withBlobs(glowingFurnaceCase("media-albedo-1-forward-g-0.95-grid-smoke-keeps-wall-radiance", 1, gridSmoke(0.95), withSamples(16)), smokeGrid),
	// Henyey-Greenstein lobes of g = +-0.999, (1 - g)^2 = 1e-6 wide: the same Le. Single
	// scattering finds the walls in the lobe by phase-function samples (weighed against
	// light samples by MIS), and light scattered more than once is path traced
	// (|g| >= path_traced_media_min_abs_g: the volume photon map, whose k photons a lobe
	// that narrow cannot weigh, is not planned).
	glowingFurnaceCase("media-albedo-1-forward-g-0.999-keeps-wall-radiance", 1, fog(1, 1, 0.999), withSamples(16)),
	glowingFurnaceCase("media-albedo-1-backward-g-minus-0.999-keeps-wall-radiance", 1, fog(1, 1, -0.999), withSamples(16)),
	// sigma_t 1e4 per unit, in a cube 1e-4 units across (optical depth 1 across, as above):
	// free flights of 1e-4 units, ray offsets of the same order. (In a unit cube the centre
	// would be 5,000 mean free paths from the walls, which an albedo-1 random walk crosses
	// in about 5,000^2 scatterings: no finite path reaches the answer, Le.)
	glowingFurnaceCase("media-sigma-t-1e4-in-a-1e-4-cube-keeps-wall-radiance", 1e-4, fog(1, 1e4, 0), nil),
	// sigma_t 1e-6 per unit: 1 - exp(-sigma_t d) ~ 5e-7, which float arithmetic loses unless
	// it is computed as -expm1 (the truncated free-flight density divides by it); almost no
	// volume photon is stored.
	glowingFurnaceCase("media-sigma-t-1e-6-keeps-wall-radiance", 1, fog(1, 1e-6, 0), nil),
	// A light inside the medium: a sphere light of the walls' radiance hanging in the fog,
	// in view. Every surface still sends Le, so the radiance is still Le: the light's own
	// emission is attenuated on its way, its shadow rays and photons travel through fog.
	glowingFurnaceCase("media-sphere-light-inside-albedo-1-fog-keeps-wall-radiance", 1, fog(1, 1, 0), withLamp),
	// A medium inside glass (withMurkyBall): a glass ball filled with an albedo-1 medium in
	// the glowing cube, in vacuum, seen from near the wall with its silhouette in view.
	// Glass and medium lose nothing, so the radiance in the ball is n^2 Le and out of it
	// Le: the ball is invisible. Light scattered inside meets the glass beyond the critical
	// angle and stays in by total internal reflection until it scatters out; camera rays
	// at the silhouette enter at grazing angles.
	glowingFurnaceCase("media-murky-glass-ball-total-internal-reflection-is-invisible", 1, nil, withMurkyBall),
	// The glowing cube filled with a medium of albedo 0: every pixel is Le exp(-sigma_t d)
	// (beerLambertCase); with sigma_t 1e-6, 2 and 1e4 in R, G and B.
	beerLambertCase("media-albedo-0-fog-sees-walls-through-beer-lambert", fog(0, 2, 0)),
	beerLambertCase("media-absorption-1e-6-2-1e4-per-channel-beer-lambert", absorbing(rgb(1e-6, 2, 1e4))),
	// The camera and the light inside fog in the closed Cornell box (foggyCornell): fog of
	// sigma_t 1e-6 per mm (optical depth under 1e-3 across the box) changes the image by
	// less than its noise.
	{
		name:  "media-fog-sigma-t-1e-6-around-camera-and-light-changes-nothing",
		scene: func(t *testing.T) *pb.Scene { return foggyCornell(t, fog(0.8, 1e-6, 0.5)) },
		check: func(t *testing.T, f *farm, name string, sc *pb.Scene, r *rendered) {
			ref := reference(t, f, "inside-cornell", func() *pb.Scene { return insideCornell(t) })
			checkMeansClose(t, name, r.img, ref.img, beauty, 0.02, "the same box without fog")
			checkMeansClose(t, name, r.img, ref.img, []string{"direct.R", "direct.G", "direct.B"}, 0.01, "the same box without fog")
			checkPixelsClose(t, name, r.img, ref.img, "direct.R", 0.05, 0.005, 0.02, "the same box without fog")
		},
	},
	// Fog of sigma_t 1e4 per mm and albedo 0.5 around the camera: the nearest surface is
	// 61 mm (6e5 mean free paths) away, the light 280 mm; light decays in it as exp(-sigma_t
	// sqrt(3 (1 - albedo)) r) (diffusion), so nothing reaches the camera: black. (With
	// albedo 1 the answer would not be black, and no path of finite length would find it.)
	{
		name: "media-fog-sigma-t-1e4-albedo-0.5-around-the-camera-is-black",
		scene: func(t *testing.T) *pb.Scene {
			s := foggyCornell(t, fog(0.5, 1e4, 0))
			s.Film = &pb.Film{Width: 16, Height: 16, TileSize: 16}
			return s
		},
		check: func(t *testing.T, f *farm, name string, sc *pb.Scene, r *rendered) {
			checkBound(t, name, r.img, [3]float64{}, "black: exp(-1e4 sqrt(1.5) 61) of anything reaches the camera")
		},
	},
}

func TestStiffAndExtremeCases(t *testing.T) {
	f := startSuiteFarm(t)
	suiteStart := time.Now()
	for _, c := range cases {
		if c.heavy && !*heavy {
			// Not run at all (rather than a subtest that passes without asserting anything).
			t.Logf("case %s: not run; it runs with -stiff.heavy (go test ./tests/stiff -args -stiff.heavy)", c.name)
			continue
		}
		t.Run(c.name, func(t *testing.T) {
			sc := c.scene(t)
			timeout := c.timeout
			if timeout == 0 {
				timeout = 60 * time.Second
			}
			if c.blobs != nil {
				for _, b := range c.blobs() {
					if _, err := f.Client.UploadBytes(context.Background(), b); err != nil {
						t.Fatalf("case %s: upload: %v", c.name, err)
					}
				}
			}
			r := f.render(t, c.name, sc, timeout)
			checkFinite(t, c.name, r.img)
			bound, why := brightestEmitter(sc), "the brightest emitter's radiance, over 1 - its reflectance"
			if c.bound != nil {
				bound, why = c.bound(sc)
			}
			if bound == [3]float64{} {
				t.Fatalf("case %s: no energy bound (no emitter and no stated bound)", c.name)
			}
			checkBound(t, c.name, r.img, bound, why)
			if c.check != nil {
				c.check(t, f, c.name, sc, r)
			}
			if t.Failed() {
				t.Logf("case %s: the job's plan: %s", c.name, planOf(f, r.job))
			}
		})
	}
	t.Logf("stiff suite: %d cases in %s", len(cases), time.Since(suiteStart).Round(time.Millisecond))
}

// checkBoundReflected fails if direct + indirect + caustic exceeds bound in any pixel.
func checkBoundReflected(t *testing.T, name string, im *image, bound [3]float64, why string) {
	t.Helper()
	for k, col := range beauty {
		worst, wx, wy, over := 0.0, 0, 0, 0
		for y := 0; y < im.height; y++ {
			for x := 0; x < im.width; x++ {
				v := sumOf(im, x, y, reflected[k][:]...)
				if v > bound[k]*(1+1e-4) {
					over++
				}
				if v > worst {
					worst, wx, wy = v, x, y
				}
			}
		}
		if over > 0 {
			t.Errorf("case %s: channel %s: direct+indirect+caustic above %.6g (%s) in %d pixels; brightest %.6g at (%d, %d)",
				name, col, bound[k], why, over, worst, wx, wy)
		}
	}
}

// checkEveryPixel fails if any pixel of channel ch is off want by more than tol relative.
func checkEveryPixel(t *testing.T, name string, im *image, ch string, want, tol float64, what string) {
	t.Helper()
	c := im.channel(ch)
	bad, wx, wy, worst := 0, 0, 0, want
	for y := 0; y < im.height; y++ {
		for x := 0; x < im.width; x++ {
			v := im.at(x, y, c)
			if !(math.Abs(v-want) <= tol*want) {
				bad++
				if math.Abs(v-want) > math.Abs(worst-want) || bad == 1 {
					worst, wx, wy = v, x, y
				}
			}
		}
	}
	if bad > 0 {
		t.Errorf("case %s: channel %s: %d of %d pixels off %s (%.6g) by more than %.3g%%; worst %.6g at (%d, %d)",
			name, ch, bad, im.width*im.height, what, want, 100*tol, worst, wx, wy)
	}
}

// insideGlass is the closed Cornell box seen from inside a glass ball (index 1.5, radius
// 40 mm) whose centre is offset (in radii, along x) from the camera.
func insideGlass(t *testing.T, offset float64) *pb.Scene {
	s := insideCornell(t)
	p := s.Camera.Position
	s.Materials = append(s.Materials, glass("glass", 1.5))
	s.Shapes = append(s.Shapes, sphere("ball", "glass", v3(p.X-offset*40, p.Y, p.Z), 40))
	return s
}

func glassBound(ior float64) func(sc *pb.Scene) ([3]float64, string) {
	return func(sc *pb.Scene) ([3]float64, string) {
		le := brightestEmitter(sc)
		n2 := ior * ior
		return [3]float64{le[0] * n2, le[1] * n2, le[2] * n2}, "n^2 times the brightest emitter's radiance (the camera is inside glass)"
	}
}

// fewPhotonsBound: however few photon paths there are, all of them together carry at
// most the light's power Phi (in every channel at most pi max(Le) A: Russian roulette
// keeps a photon's largest channel), and a radiance estimate that divides by the search
// disc spreads what it finds over at least the disc of the map's maximum radius (by
// default 1/20 of the shapes' bounding-box diagonal for the global map, 1/100 for the
// caustic map). So no pixel may exceed Le + sum over both maps of (1/pi) Phi / (pi r_max^2).
// An estimate that divides the power of one photon found very close by the square of
// that tiny distance breaks it.
func fewPhotonsBound(sc *pb.Scene) ([3]float64, string) {
	le := brightestEmitter(sc)
	diag := math.Sqrt(556*556 + 548.8*548.8 + 559.2*559.2) // the Cornell box's shapes
	phi := math.Pi * math.Max(le[0], math.Max(le[1], le[2])) * cornellLightArea
	perDisc := 0.0
	for _, rmax := range []float64{diag / 20, diag / 100} {
		perDisc += (1 / math.Pi) * phi / (math.Pi * rmax * rmax)
	}
	return [3]float64{le[0] + perDisc, le[1] + perDisc, le[2] + perDisc},
		"Le plus the light's whole power spread over the smallest default search disc of each map"
}

// fewPhotons is the Cornell box with a glass ball and n global and n caustic photon paths.
func fewPhotons(t *testing.T, n uint64) *pb.Scene {
	s := glassInCornell(t, 1.5)
	s.Photons = &pb.PhotonMapping{GlobalPhotons: n, CausticPhotons: n}
	return s
}

// checkFewPhotons: direct light uses no photons, so it equals that of 20,000 photons.
func checkFewPhotons(t *testing.T, f *farm, name string, sc *pb.Scene, r *rendered) {
	ref := reference(t, f, "cornell-glass-1.5", func() *pb.Scene { return glassInCornell(t, 1.5) })
	checkMeansClose(t, name, r.img, ref.img, []string{"direct.R", "direct.G", "direct.B"}, 0.01, "the same scene with 20,000 photons (direct light uses no photons; edge anti-aliasing may move a few samples)")
}

// manyPhotons is the Cornell box with a glass ball and n global and n caustic photon
// paths in shards of n/4, on a 16x16 film with one sample per pixel.
func manyPhotons(t *testing.T, n uint64) *pb.Scene {
	s := glassInCornell(t, 1.5)
	s.Film = &pb.Film{Width: 16, Height: 16, TileSize: 16}
	s.Sampling.SamplesPerPixel = 1
	s.Photons = &pb.PhotonMapping{GlobalPhotons: n, CausticPhotons: n, PhotonsPerShard: n / 4}
	return s
}

// checkManyPhotons: the job ends within budget, and its image agrees on average with the
// same scene at 20,000 photons (the photon maps' expectation does not depend on the count).
func checkManyPhotons(budget time.Duration) func(t *testing.T, f *farm, name string, sc *pb.Scene, r *rendered) {
	return func(t *testing.T, f *farm, name string, sc *pb.Scene, r *rendered) {
		if r.elapsed > budget {
			t.Errorf("case %s: %d photon paths per map took %s, budget %s", name, sc.Photons.GlobalPhotons, r.elapsed.Round(time.Millisecond), budget)
		}
		ref := reference(t, f, "many-photons-20k", func() *pb.Scene { return manyPhotons(t, 20000) })
		checkMeansClose(t, name, r.img, ref.img, beauty, 0.1, "20,000 photons")
	}
}

// furnaceSpec says how a white furnace case is rendered.
type furnaceSpec struct {
	rho    float64
	paths  uint64          // global photon paths (per round)
	rounds uint32          // progressive rounds; 0 or 1: one
	mode   pb.IndirectMode // unspecified: the scene's default
	decoy  bool            // add a tiny diffuse ball outside the furnace
}

// furnaceNeighbours is k for the global map: the k-nearest estimate is biased by about
// 1/(k - 1) of the indirect light (0.4% of the image at rho 0.8), well inside 1%.
const furnaceNeighbours = 200

// furnaceCase renders a white furnace with enough photons that the image average is
// within 1% of the analytic radiance, and every pixel within 20%.
func furnaceCase(spec furnaceSpec) stiffCase {
	want := furnaceRadiance(spec.rho)
	name := "white-furnace-rho-" + trimFloat(spec.rho)
	switch {
	case spec.rounds > 1:
		name += "-in-" + strconv.Itoa(int(spec.rounds)) + "-progressive-rounds"
	case spec.mode == pb.IndirectMode_INDIRECT_MODE_FINAL_GATHER:
		name += "-final-gathering-conserves-energy"
	case spec.mode == pb.IndirectMode_INDIRECT_MODE_PHOTON_MAP:
		name += "-photon-map-seen-directly-conserves-energy"
	default:
		name += "-returns-furnace-radiance"
	}
	return stiffCase{
		name:    name,
		timeout: 2 * time.Minute,
		scene: func(t *testing.T) *pb.Scene {
			s := furnace(spec.rho, spec.paths, furnaceNeighbours)
			if spec.rounds > 1 {
				s.Progressive = &pb.Progressive{MaxRounds: spec.rounds}
			}
			if spec.mode != pb.IndirectMode_INDIRECT_MODE_UNSPECIFIED {
				s.Indirect = &pb.Indirect{Mode: spec.mode}
			}
			if spec.decoy {
				s.Shapes = append(s.Shapes, sphere("decoy", "wall", v3(10, 10, 10), 0.01))
			}
			return s
		},
		bound: furnaceBound(want),
		check: checkFurnace(want, "furnace radiance rho Phi / (pi A (1 - rho))"),
	}
}

// furnaceBound is the energy bound of a furnace, where every pixel's true radiance is
// want: want is then both the answer and the brightest any pixel may be, so the bound
// allows what checkFurnace allows a pixel, want + 20%.
func furnaceBound(want float64) func(sc *pb.Scene) ([3]float64, string) {
	return func(sc *pb.Scene) ([3]float64, string) {
		l := want * 1.2
		return [3]float64{l, l, l}, "the furnace radiance + 20%"
	}
}

// checkFurnace checks a furnace whose every pixel's true radiance is want (what says why):
// the image average within 1% in every colour, every pixel within 20%.
func checkFurnace(want float64, what string) func(t *testing.T, f *farm, name string, sc *pb.Scene, r *rendered) {
	return func(t *testing.T, f *farm, name string, sc *pb.Scene, r *rendered) {
		for _, ch := range beauty {
			checkClose(t, name, ch, "image average ("+what+")", mean(t, name, r.img, ch, nil), want, 0.01)
			checkEveryPixel(t, name, r.img, ch, want, 0.2, "the furnace radiance")
		}
	}
}

// glowingFurnaceCase renders the glowing cube s units across filled with the albedo-1
// medium m (nil: vacuum) and changed by dress (nil: none), whose every pixel's radiance
// must be the walls' Le, every pixel within 20% (the bound, as for the white furnace).
func glowingFurnaceCase(name string, s float64, m *pb.Medium, dress func(sc *pb.Scene)) stiffCase {
	return stiffCase{
		name:    name,
		timeout: 2 * time.Minute,
		scene: func(t *testing.T) *pb.Scene {
			sc := glowingCube(s, m)
			if dress != nil {
				dress(sc)
			}
			return sc
		},
		bound: furnaceBound(glowingLe),
		check: checkFurnace(glowingLe, "the walls' radiance Le: nothing in the cube loses light"),
	}
}

// beerLambertCase renders the unit glowing cube filled with m, a medium that scatters
// nothing. No light is then added along a camera ray (these media do not emit) and the
// far wall's Le is seen through the medium: L = Le exp(-sigma_t d) per channel, d the
// distance to the wall (checkBeerLambert). Not Le: an absorbing medium would keep the
// enclosure's Le only if it also emitted sigma_a Le (Kirchhoff: thermal equilibrium).
func beerLambertCase(name string, m *pb.Medium) stiffCase {
	return stiffCase{
		name:  name,
		scene: func(t *testing.T) *pb.Scene { return glowingCube(1, m) },
		check: func(t *testing.T, f *farm, name string, sc *pb.Scene, r *rendered) {
			checkBeerLambert(t, name, r.img, glowingLe, sigmaT(m), 0.5)
		},
	}
}

// checkBeerLambert checks the glowing cube seen through an absorbing medium, the far wall
// depth units ahead of the camera (90-degree field of view, square film): a ray through
// screen position (sx, sy) in [-1, 1]^2 meets the wall at d = depth sqrt(1 + sx^2 + sy^2)
// and brings le exp(-sigma_t d). A pixel is the mean of samples within it (the box
// filter), so it lies between the least and the largest of that over the pixel, which
// its corners nearest and farthest from the image centre give (float rounding aside:
// relative 1e-4 and 1e-7). The image average is within 1% of the exact mean over the
// film (a 16 x 16 midpoint rule in each pixel).
func checkBeerLambert(t *testing.T, name string, im *image, le float64, sigma [3]float64, depth float64) {
	t.Helper()
	radiance := func(k int, sx, sy float64) float64 { return le * math.Exp(-sigma[k]*depth*math.Sqrt(1+sx*sx+sy*sy)) }
	screen := func(i, n int) (lo, hi float64) { return 2*float64(i)/float64(n) - 1, 2*float64(i+1)/float64(n) - 1 }
	near := func(lo, hi float64) float64 { // the least |s| over [lo, hi]
		if lo <= 0 && hi >= 0 {
			return 0
		}
		return math.Min(math.Abs(lo), math.Abs(hi))
	}
	far := func(lo, hi float64) float64 { return math.Max(math.Abs(lo), math.Abs(hi)) }
	const sub = 16
	for k, col := range beauty {
		c := im.channel(col)
		bad, worst, wx, wy, wlo, whi := 0, 0.0, 0, 0, 0.0, 0.0
		exact := 0.0
		for y := 0; y < im.height; y++ {
			ylo, yhi := screen(y, im.height)
			for x := 0; x < im.width; x++ {
				xlo, xhi := screen(x, im.width)
				lo, hi := radiance(k, far(xlo, xhi), far(ylo, yhi)), radiance(k, near(xlo, xhi), near(ylo, yhi))
				v := im.at(x, y, c)
				if off := math.Max(lo*(1-1e-4)-1e-7-v, v-hi*(1+1e-4)-1e-7); !(off <= 0) {
					bad++
					if off > worst || bad == 1 {
						worst, wx, wy, wlo, whi = off, x, y, lo, hi
					}
				}
				for j := 0; j < sub; j++ {
					for i := 0; i < sub; i++ {
						exact += radiance(k, xlo+(xhi-xlo)*(float64(i)+0.5)/sub, ylo+(yhi-ylo)*(float64(j)+0.5)/sub)
					}
				}
			}
		}
		if bad > 0 {
			t.Errorf("case %s: channel %s: %d of %d pixels outside Le exp(-sigma_t d) over the pixel; worst (%d, %d) = %.6g, want within [%.6g, %.6g]",
				name, col, bad, im.width*im.height, wx, wy, im.at(wx, wy, c), wlo, whi)
		}
		exact /= float64(im.width * im.height * sub * sub)
		checkClose(t, name, col, "image average (Le exp(-sigma_t d) over the film)", mean(t, name, im, col, nil), exact, 0.01)
	}
}

func trimFloat(v float64) string { return strconv.FormatFloat(v, 'g', -1, 64) }

// planOf is the job's plan (which passes ran, which were skipped and why), for a failure.
func planOf(f *farm, job *pb.Job) string {
	ctx, cancel := context.WithTimeout(context.Background(), 5*time.Second)
	defer cancel()
	if j, err := f.Client.GetJob(ctx, job.GetId()); err == nil {
		job = j
	}
	var parts []string
	for _, p := range job.GetPlan().GetPasses() {
		state := "skip"
		if p.GetEnabled() {
			state = "run"
		}
		parts = append(parts, fmt.Sprintf("%s %s (%s)", state, p.GetName(), p.GetReason()))
	}
	if len(parts) == 0 {
		return "(none recorded)"
	}
	return strings.Join(parts, "; ")
}
