package planner_test

import (
	"fmt"
	"math"
	"strconv"
	"strings"
	"testing"

	"photonfarm/contract/rules"
	"photonfarm/contract/scene"
	"photonfarm/contract/scene/scenetest"
	"photonfarm/coordinator/planner"
	pb "photonfarm/proto/renderfarm/v1"
)

// passOf returns the pass called name.
func passOf(t *testing.T, p *pb.Plan, name string) *pb.PlannedPass {
	t.Helper()
	for _, ps := range p.GetPasses() {
		if ps.GetName() == name {
			return ps
		}
	}
	t.Fatalf("plan has no pass %q: %v", name, p)
	return nil
}

// absorbingFog fills the scene with a medium that only absorbs; scatteringFog with one
// that also scatters.
func absorbingFog(s *pb.Scene) {
	s.Medium = &pb.Medium{Coefficients: &pb.Medium_Sigma{Sigma: &pb.MediumCoefficients{SigmaA: &pb.Color{R: 0.1}, SigmaS: &pb.Color{}}}}
}

func scatteringFog(s *pb.Scene) {
	s.Medium = &pb.Medium{Coefficients: &pb.Medium_Sigma{Sigma: &pb.MediumCoefficients{SigmaA: &pb.Color{R: 0.1}, SigmaS: &pb.Color{B: 0.05}}}}
}

// pathTracedG is the contract's path_traced_media_min_abs_g, absG as the plan writes it.
var (
	pathTracedG = rules.Scene.GetPathTracedMediaMinAbsG()
	absG        = strconv.FormatFloat(pathTracedG, 'g', -1, 64)
)

// peakedFog fills the scene with scatteringFog of Henyey-Greenstein asymmetry g.
func peakedFog(g float64) func(*pb.Scene) {
	return func(s *pb.Scene) {
		scatteringFog(s)
		s.Medium.G = g
	}
}

// smokeIn makes the ball (shapes[0]) of the material named kind ("white", "mirror",
// "glass"), filled with a scattering medium.
func smokeIn(kind string) func(*pb.Scene) {
	return func(s *pb.Scene) {
		shapes(kind, "white")(s)
		s.Shapes[0].InteriorMedium = &pb.Medium{Coefficients: &pb.Medium_Albedo{Albedo: &pb.MediumAlbedo{Albedo: &pb.Color{R: 0.9, G: 0.9, B: 0.9}, Density: 2}}}
	}
}

func TestPassesSayWhatRunsAndWhy(t *testing.T) {
	flatFloor := func(s *pb.Scene) { s.Shapes = s.Shapes[1:] } // floor and lamp only
	sky := &pb.Texture{Name: "sky", Path: "sky.hdr", Digest: "sha256:" + strings.Repeat("0", 64)}
	tests := []struct {
		name   string
		mutate func(*pb.Scene)
		pass   string
		run    bool
		reason string
	}{
		{"diffuse sphere on a floor", func(*pb.Scene) {}, planner.PassGlobalMap, true, "can light each other"},
		{"one plane of diffuse surfaces", flatFloor, planner.PassGlobalMap, false, "one plane"},
		{"one plane: no gathering", flatFloor, planner.PassFinalGather, false, "no global photon map"},
		{"one sphere lit from outside", func(s *pb.Scene) { s.Shapes = append(s.Shapes[:1], s.Shapes[2]) }, planner.PassGlobalMap, false, "one sphere lit from outside"},
		{"one sphere with the light inside (a furnace)", func(s *pb.Scene) {
			s.Shapes = s.Shapes[:1]
			s.Lights = []*pb.Light{{Kind: &pb.Light_Point{Point: &pb.PointLight{Position: scenetest.V(0, 1, 0), Intensity: &pb.Color{R: 1, G: 1, B: 1}}}}}
		}, planner.PassGlobalMap, true, "can light each other"},
		{"one plane with a mirror", func(s *pb.Scene) {
			flatFloor(s)
			s.Materials = append(s.Materials, material("mirror", "mirror"))
			s.Shapes = append(s.Shapes, &pb.Shape{Material: "mirror", Geometry: &pb.Shape_Sphere{Sphere: &pb.Sphere{Center: scenetest.V(0, 1, 0), Radius: 1}}})
		}, planner.PassGlobalMap, true, "specular"},
		{"no specular surface", func(*pb.Scene) {}, planner.PassCausticMap, false, "no specular surface (mirror, glass, metal)"},
		{"glass ball", shapes("glass", "white"), planner.PassCausticMap, true, "specular surfaces focus light"},
		{"final gathering by default", func(*pb.Scene) {}, planner.PassFinalGather, true, "64 gather rays"},
		{"precompute by default", func(*pb.Scene) {}, planner.PassPrecompute, true, "2 shards per round"},
		{"photon map mode", func(s *pb.Scene) { s.Indirect = &pb.Indirect{Mode: pb.IndirectMode_INDIRECT_MODE_PHOTON_MAP} }, planner.PassFinalGather, false, "PHOTON_MAP"},
		{"direct light", func(*pb.Scene) {}, planner.PassDirect, true, "1 light"},
		{"an instanced mesh's emissive parts are lights", func(s *pb.Scene) {
			digest := "sha256:" + strings.Repeat("0", 64)
			s.Meshes = []*pb.Mesh{{Name: "lantern", Parts: []*pb.MeshPart{{Digest: digest, Material: "light"}, {Digest: digest, Material: "white"}}}}
			for range 2 {
				s.Shapes = append(s.Shapes, &pb.Shape{Geometry: &pb.Shape_Instance{Instance: &pb.MeshInstance{Mesh: "lantern"}}})
			}
		}, planner.PassDirect, true, "3 lights"},
		{"an instanced diffuse part over one plane", func(s *pb.Scene) {
			flatFloor(s)
			s.Meshes = []*pb.Mesh{{Name: "box", Parts: []*pb.MeshPart{{Digest: "sha256:" + strings.Repeat("0", 64), Material: "white"}}}}
			s.Shapes = append(s.Shapes, &pb.Shape{Geometry: &pb.Shape_Instance{Instance: &pb.MeshInstance{Mesh: "box"}}})
		}, planner.PassGlobalMap, true, "can light each other"},
		{"no medium: no marching", func(*pb.Scene) {}, planner.PassMedia, false, "no medium in the scene"},
		{"no medium: no volume map", func(*pb.Scene) {}, planner.PassVolumeMap, false, "no medium in the scene: no volume photons"},
		{"fog and a murky ball", func(s *pb.Scene) {
			fog := &pb.Medium{Coefficients: &pb.Medium_Albedo{Albedo: &pb.MediumAlbedo{Albedo: &pb.Color{R: 0.9, G: 0.9, B: 0.9}, Density: 0.1}}}
			s.Medium = fog
			s.Shapes[0].InteriorMedium = fog
		}, planner.PassMedia, true, "fog filling the scene and 1 shape's interior medium: camera paths attenuated"},
		{"absorbing fog: no volume map", absorbingFog, planner.PassVolumeMap, false, "no medium scatters light (every sigma_s is 0, or every albedo or density is): the media only absorb, no volume photons"},
		{"a murky ball without density: no volume map", func(s *pb.Scene) {
			s.Shapes[0].InteriorMedium = &pb.Medium{Coefficients: &pb.Medium_Albedo{Albedo: &pb.MediumAlbedo{Albedo: &pb.Color{R: 0.9, G: 0.9, B: 0.9}}}}
		}, planner.PassVolumeMap, false, "the media only absorb"},
		{"scattering fog: volume map", scatteringFog, planner.PassVolumeMap, true,
			"200,000 volume photon paths per round in 2 shards: photons stored where paths scatter in media of |g| < " + absG + " after their first bounce or scattering, gathered along camera and gather rays (k 50, radius 1/20 of the scene's diagonal)"},
		{"scattering fog: volume map of the scene's photons and estimate", func(s *pb.Scene) {
			scatteringFog(s)
			s.Photons.VolumePhotons, s.Photons.PhotonsPerShard = 25000, 10000
			s.Photons.VolumeEstimate = &pb.RadianceEstimate{Neighbours: 80, MaxRadius: 0.25}
		}, planner.PassVolumeMap, true, "25,000 volume photon paths per round in 3 shards: photons stored where paths scatter in media of |g| < " + absG + " after their first bounce or scattering, gathered along camera and gather rays (k 80, radius 0.25)"},
		{"scattering fog: multiple scattering", scatteringFog, planner.PassMedia, true, "fog filling the scene: camera paths attenuated and single scattering from every light along them (16 light samples and as many phase-function samples per segment, weighed by multiple importance sampling), shadow rays attenuated; multiple scattering from the volume photon map"},
		// At |g| >= path_traced_media_min_abs_g the volume map's k photons cannot weigh the
		// phase function's lobe: such media are path traced, and a scene of only such media
		// gets no volume map.
		{"forward-scattering fog: no volume map", peakedFog(pathTracedG), planner.PassVolumeMap, false,
			"every medium light reaches that scatters it has |g| >= " + absG + ": its multiple scattering is path traced, no volume photons"},
		{"backward-scattering fog: path traced", peakedFog(-0.999), planner.PassMedia, true,
			"; multiple scattering by volumetric path tracing (camera paths go on by the phase function, with light samples weighed by MIS): |g| >= " + absG},
		{"fog just below the threshold: volume map", peakedFog(math.Nextafter(pathTracedG, 0)), planner.PassVolumeMap, true, "200,000 volume photon paths per round"},
		{"forward-scattering fog and an isotropic murky glass ball: both", func(s *pb.Scene) {
			smokeIn("glass")(s)
			peakedFog(0.95)(s)
		}, planner.PassMedia, true, "; multiple scattering from the volume photon map, and by volumetric path tracing (camera paths go on by the phase function, with light samples weighed by MIS) in media of |g| >= " + absG},
		{"forward-scattering fog and an isotropic murky glass ball: volume map", func(s *pb.Scene) {
			smokeIn("glass")(s)
			peakedFog(0.95)(s)
		}, planner.PassVolumeMap, true, "200,000 volume photon paths per round"},
		{"fog lit by a point light alone: light samples only", func(s *pb.Scene) {
			scatteringFog(s)
			s.Shapes = s.Shapes[:len(s.Shapes)-1] // the lamp
			s.Lights = []*pb.Light{{Kind: &pb.Light_Point{Point: &pb.PointLight{Position: scenetest.V(0, 2, 0), Intensity: &pb.Color{R: 1, G: 1, B: 1}}}}}
		}, planner.PassMedia, true, "(16 light samples per segment: no phase-function sample can reach a point, spot or sun light without a disc)"},
		{"absorbing forward-scattering fog: it only absorbs", func(s *pb.Scene) { absorbingFog(s); s.Medium.G = 0.95 }, planner.PassVolumeMap, false, "the media only absorb"},
		{"smoke in a closed diffuse ball, the light outside: no volume map", smokeIn("white"), planner.PassVolumeMap, false,
			`no medium that light reaches scatters it, no volume photons: shapes[0] ("ball")'s interior medium: no light reaches it: its surface transmits none`},
		{"smoke in a mirror ball is dark too", smokeIn("mirror"), planner.PassVolumeMap, false, `shapes[0] ("ball")'s interior medium: no light reaches it`},
		{"smoke in a glass ball is lit", smokeIn("glass"), planner.PassVolumeMap, true, "200,000 volume photon paths per round in 2 shards"},
		{"smoke in a diffuse ball with a light inside is lit", func(s *pb.Scene) {
			smokeIn("white")(s)
			s.Lights = append(s.Lights, &pb.Light{Kind: &pb.Light_Point{Point: &pb.PointLight{Position: scenetest.V(0, 1, 0.5), Intensity: &pb.Color{R: 1, G: 1, B: 1}}}})
		}, planner.PassVolumeMap, true, "200,000 volume photon paths per round"},
		{"smoke in a diffuse ball beside scattering fog: the fog's photons, none for the ball", func(s *pb.Scene) {
			smokeIn("white")(s)
			scatteringFog(s)
		}, planner.PassVolumeMap, true, `(k 50, radius 1/20 of the scene's diagonal); none for shapes[0] ("ball")'s interior medium: no light reaches it`},
		{"smoke from a grid", func(s *pb.Scene) {
			s.Medium = &pb.Medium{Coefficients: &pb.Medium_Grid{Grid: &pb.MediumGrid{Digest: "sha256:" + strings.Repeat("0", 64), Albedo: &pb.Color{R: 0.9, G: 0.9, B: 0.9}}}}
		}, planner.PassMedia, true, "smoke from a grid filling the scene: camera paths attenuated and single scattering from every light along them (16 light samples and as many phase-function samples per segment, weighed by multiple importance sampling), shadow rays attenuated; through grids brick by brick (8^3 cells, empty ones skipped): optical depth integrated exactly, distances drawn by inverting it, free flights (photons, volumetric paths) delta-tracked against each brick's majorant; multiple scattering from the volume photon map"},
		{"forward-scattering smoke from a grid: path traced", func(s *pb.Scene) {
			s.Medium = &pb.Medium{G: 0.95, Coefficients: &pb.Medium_Grid{Grid: &pb.MediumGrid{Digest: "sha256:" + strings.Repeat("0", 64), Albedo: &pb.Color{R: 0.9, G: 0.9, B: 0.9}}}}
		}, planner.PassVolumeMap, false, "every medium light reaches that scatters it has |g| >= " + absG + ": its multiple scattering is path traced, no volume photons"},
		{"forward-scattering fog beside smoke in a closed diffuse ball: no volume map", func(s *pb.Scene) {
			smokeIn("white")(s)
			peakedFog(0.95)(s)
		}, planner.PassVolumeMap, false, `its multiple scattering is path traced, no volume photons; none for shapes[0] ("ball")'s interior medium: no light reaches it`},
		{"no dispersion", shapes("glass", "white"), planner.PassDispersion, false, "no dispersive material"},
		{"a dispersive glass and a gem", func(s *pb.Scene) {
			prism, gem := material("prism", "glass"), material("gem", "glass")
			prism.GetDielectric().Dispersion = &pb.Dispersion{Law: &pb.Dispersion_Glass{Glass: pb.Glass_GLASS_BK7}}
			gem.GetDielectric().Dispersion = &pb.Dispersion{Law: &pb.Dispersion_AbbeNumber{AbbeNumber: 30}}
			s.Materials = append(s.Materials, prism, gem)
			s.Shapes[0].Material, s.Shapes[1].Material = "gem", "prism"
		}, planner.PassDispersion, true, `material "gem" (Abbe number 30), material "prism" (BK7): light through it is traced at one wavelength`},
		{"spectral everywhere", func(s *pb.Scene) {
			s.Sampling = &pb.Sampling{Spectral: pb.SpectralSampling_SPECTRAL_SAMPLING_ALWAYS}
		}, planner.PassDispersion, true, fmt.Sprintf("sampling.spectral is ALWAYS: every photon and camera path is traced at %d wavelengths from its start (a hero and its companions), colours uplifted to spectra; no dispersive material", rules.Scene.GetSpectralWavelengthsPerPath())},
		{"spectral everywhere through a prism", func(s *pb.Scene) {
			prism := material("prism", "glass")
			prism.GetDielectric().Dispersion = &pb.Dispersion{Law: &pb.Dispersion_Glass{Glass: pb.Glass_GLASS_BK7}}
			s.Materials = append(s.Materials, prism)
			s.Shapes[0].Material = "prism"
			s.Sampling = &pb.Sampling{Spectral: pb.SpectralSampling_SPECTRAL_SAMPLING_ALWAYS}
		}, planner.PassDispersion, true, `material "prism" (BK7): past it only the hero wavelength goes on`},
		{"edges by default", func(*pb.Scene) {}, planner.PassEdgeAA, true, "32 samples on edge pixels"},
		{"an environment is one more light", func(s *pb.Scene) {
			s.Environment = &pb.Environment{Radiance: &pb.Color{R: 0.2, G: 0.3, B: 0.5}}
		}, planner.PassDirect, true, "shadow rays to 1 light and the environment ("},
		{"an environment map is one more light", func(s *pb.Scene) {
			s.Textures = []*pb.Texture{sky}
			s.Environment = &pb.Environment{Map: &pb.TextureRef{Texture: "sky"}}
		}, planner.PassDirect, true, "1 light and the environment ("},
		{"a black environment is left out", func(s *pb.Scene) {
			s.Textures = []*pb.Texture{sky}
			s.Environment = &pb.Environment{Radiance: &pb.Color{}, Map: &pb.TextureRef{Texture: "sky"}}
		}, planner.PassDirect, true, "1 light; the environment is black: no shadow rays to it and no photons from it ("},
		{"no antialiasing", func(s *pb.Scene) { s.Antialiasing = &pb.Antialiasing{Mode: pb.AntialiasingMode_ANTIALIASING_MODE_NONE} }, planner.PassEdgeAA, false, "NONE"},
		{"full supersampling", func(s *pb.Scene) { s.Antialiasing = &pb.Antialiasing{Mode: pb.AntialiasingMode_ANTIALIASING_MODE_FULL} }, planner.PassEdgeAA, true, "FULL"},
		{"one round", func(*pb.Scene) {}, planner.PassRounds, false, "a single round"},
		{"rounds with a target and a budget", func(s *pb.Scene) {
			s.Progressive = &pb.Progressive{MaxRounds: 8, TargetError: 0.01, TimeBudgetSeconds: 60}
		}, planner.PassRounds, true, "up to 8 rounds, stop at estimated error <= 0.01, no new round after 60s"},
		{"adaptive sampling off by default", func(*pb.Scene) {}, planner.PassAdaptive, false, "OFF (the default)"},
		{"adaptive sampling on", func(s *pb.Scene) {
			s.Sampling.Adaptive = pb.AdaptiveSampling_ADAPTIVE_SAMPLING_ON
			s.Progressive = &pb.Progressive{MaxRounds: 8}
		}, planner.PassAdaptive, true, "from round 3 each pixel's camera samples follow its estimated error"},
		{"adaptive sampling needs a third round", func(s *pb.Scene) {
			s.Sampling.Adaptive = pb.AdaptiveSampling_ADAPTIVE_SAMPLING_ON
			s.Progressive = &pb.Progressive{MaxRounds: 2}
		}, planner.PassAdaptive, false, "max_rounds is 2"},
		{"adaptive sampling needs the box filter", func(s *pb.Scene) {
			s.Sampling.Adaptive = pb.AdaptiveSampling_ADAPTIVE_SAMPLING_ON
			s.Progressive = &pb.Progressive{MaxRounds: 8}
			s.Film.Filter = &pb.PixelFilter{Kind: &pb.PixelFilter_Tent{Tent: &pb.TentFilter{}}}
		}, planner.PassAdaptive, false, "wider than the one-pixel box"},
	}
	for _, tt := range tests {
		t.Run(tt.name, func(t *testing.T) {
			s := scenetest.Valid(64, 64)
			s.Photons = &pb.PhotonMapping{GlobalPhotons: 200000}
			tt.mutate(s)
			if err := scene.Validate(s); err != nil {
				t.Fatal(err)
			}
			p := passOf(t, planner.Passes(scene.Defaults(s)), tt.pass)
			if p.GetEnabled() != tt.run || !strings.Contains(p.GetReason(), tt.reason) {
				t.Errorf("%s: run %v, %q; want run %v with %q", tt.pass, p.GetEnabled(), p.GetReason(), tt.run, tt.reason)
			}
		})
	}
}

func TestRoundsDrawFreshPhotonsAndSamplesWithShrinkingRadii(t *testing.T) {
	s := scenetest.Valid(32, 32)
	s.Sampling.SamplesPerPixel = 4
	s.Photons = &pb.PhotonMapping{GlobalPhotons: 2500, PhotonsPerShard: 1000}
	s.Progressive = &pb.Progressive{MaxRounds: 3, Alpha: 0.5}
	s = scene.Defaults(s)
	for r := uint32(1); r <= 3; r++ {
		tasks := planner.Round(s, r)
		var firsts []uint64
		for i, task := range tasks {
			if task.Round != r || task.Index != uint32(i) {
				t.Fatalf("round %d task %d: round %d index %d", r, i, task.Round, task.Index)
			}
			if e := task.GetEmitPhotons(); e != nil {
				firsts = append(firsts, e.FirstPhoton)
				if e.TotalPhotons != 2500 {
					t.Errorf("round %d: total_photons %d, want 2500 (each round's map stands alone)", r, e.TotalPhotons)
				}
			}
			if rt := task.GetRenderTile(); rt != nil {
				if rt.FirstSample != 4*(r-1) {
					t.Errorf("round %d: first_sample %d, want %d", r, rt.FirstSample, 4*(r-1))
				}
				if want := planner.RadiusScale(0.5, r); rt.RadiusScale != want {
					t.Errorf("round %d: radius_scale %v, want %v", r, rt.RadiusScale, want)
				}
			}
		}
		base := uint64(2500 * (r - 1))
		if len(firsts) != 3 || firsts[0] != base || firsts[1] != base+1000 || firsts[2] != base+2000 {
			t.Errorf("round %d: emission shards start at %v, want %d, %d, %d", r, firsts, base, base+1000, base+2000)
		}
		if got := planner.PhaseCounts(tasks); len(got) != 6 || got[2].Phase != pb.Phase_PHASE_PRECOMPUTE || got[2].TasksTotal != 3 {
			t.Errorf("round %d phases = %v, want emit, build, 3 precompute, merge, render, composite", r, got)
		}
	}
	for _, tt := range []struct {
		alpha float64
		r     uint32
		want  float64
	}{{0.7, 1, 1}, {0.7, 2, math.Sqrt(1.7 / 2)}, {0.7, 3, math.Sqrt(1.7 / 2 * 2.7 / 3)}, {1, 50, 1}} {
		if got := planner.RadiusScale(tt.alpha, tt.r); math.Abs(got-tt.want) > 1e-15 {
			t.Errorf("RadiusScale(%v, %d) = %v, want %v", tt.alpha, tt.r, got, tt.want)
		}
	}
}
