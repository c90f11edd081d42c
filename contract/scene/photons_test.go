package scene_test

import (
	"math"
	"testing"

	"photonfarm/contract/rules"
	"photonfarm/contract/scene"
	"photonfarm/contract/scene/scenetest"
	pb "photonfarm/proto/renderfarm/v1"
)

func rgb(r, g, b float64) *pb.Color { return &pb.Color{R: r, G: g, B: b} }

func glossy(d, s *pb.Color, exp float64) *pb.Material {
	return &pb.Material{Name: "shiny", Kind: &pb.Material_Glossy{Glossy: &pb.Glossy{Diffuse: d, Specular: s, Exponent: exp}}}
}

func dielectric(ior float64, t *pb.Color) *pb.Material {
	return &pb.Material{Name: "glass", Kind: &pb.Material_Dielectric{Dielectric: &pb.Dielectric{Ior: ior, Transmittance: t}}}
}

func conductor(eta, k *pb.Color) *pb.Material {
	return &pb.Material{Name: "gold", Kind: &pb.Material_Conductor{Conductor: &pb.Conductor{Eta: eta, K: k}}}
}

func mirror(r *pb.Color) *pb.Material {
	return &pb.Material{Name: "mirror", Kind: &pb.Material_Mirror{Mirror: &pb.Mirror{Reflectance: r}}}
}

func point(pos *pb.Vec3, i *pb.Color) *pb.Light {
	return &pb.Light{Name: "bulb", Kind: &pb.Light_Point{Point: &pb.PointLight{Position: pos, Intensity: i}}}
}

func sun(dir *pb.Vec3, e *pb.Color) *pb.Light {
	return &pb.Light{Name: "sun", Kind: &pb.Light_Sun{Sun: &pb.SunLight{Direction: dir, Irradiance: e}}}
}

// withoutLamp removes the emissive quad (shape 2) so that only the lights remain.
func withoutLamp(s *pb.Scene) { s.Shapes = s.Shapes[:2] }

func addMaterial(m *pb.Material) func(*pb.Scene) {
	return func(s *pb.Scene) { s.Materials = append(s.Materials, m) }
}

// maxPhotons is the most photon paths a map may have.
var maxPhotons = uint64(rules.Max(&pb.PhotonMapping{}, "global_photons"))

func TestValidateAcceptsMaterialsLightsAndPhotonSettings(t *testing.T) {
	tests := []variant{
		{"glossy at the energy bound", addMaterial(glossy(rgb(0.5, 0.2, 0), rgb(0.5, 0.8, 1), 1))},
		{"glossy max exponent", addMaterial(glossy(rgb(0, 0, 0), rgb(0.9, 0.9, 0.9), 1e5))},
		{"mirror", addMaterial(mirror(rgb(1, 0.9, 0)))},
		{"dielectric without transmittance", addMaterial(dielectric(1.5, nil))},
		{"dielectric bounds", addMaterial(dielectric(10, rgb(1, 0, 0.5)))},
		{"dielectric ior 1", addMaterial(dielectric(1, nil))},
		{"conductor gold", addMaterial(conductor(rgb(0.143, 0.374, 1.442), rgb(3.983, 2.385, 1.603)))},
		{"conductor k 0", addMaterial(conductor(rgb(1, 1, 1), rgb(0, 0, 0)))},
		{"point light only", func(s *pb.Scene) {
			withoutLamp(s)
			s.Lights = []*pb.Light{point(scenetest.V(0, 3, 0), rgb(10, 10, 0))}
		}},
		{"sun light only", func(s *pb.Scene) {
			withoutLamp(s)
			s.Lights = []*pb.Light{sun(scenetest.V(0, -1, 0.2), rgb(1, 1, 1))}
		}},
		{"a dark point light next to an area light", func(s *pb.Scene) { s.Lights = []*pb.Light{point(scenetest.V(0, 3, 0), rgb(0, 0, 0))} }},
		{"photon limits", func(s *pb.Scene) {
			s.Photons = &pb.PhotonMapping{GlobalPhotons: maxPhotons, CausticPhotons: 1, PhotonsPerShard: uint64(rules.Max(&pb.PhotonMapping{}, "photons_per_shard"))}
		}},
		{"smallest shard", func(s *pb.Scene) {
			s.Photons = &pb.PhotonMapping{PhotonsPerShard: uint64(rules.Min(&pb.PhotonMapping{}, "photons_per_shard"))}
		}},
		{"estimates", func(s *pb.Scene) {
			s.Photons = &pb.PhotonMapping{
				GlobalEstimate:  &pb.RadianceEstimate{Neighbours: uint32(rules.Max(&pb.RadianceEstimate{}, "neighbours")), MaxRadius: 0.5, Filter: pb.Filter_FILTER_GAUSSIAN},
				CausticEstimate: &pb.RadianceEstimate{Neighbours: 1, Filter: pb.Filter_FILTER_CONE, ConeK: 1},
			}
		}},
		{"empty photon settings", func(s *pb.Scene) { s.Photons = &pb.PhotonMapping{} }},
	}
	expectValid(t, tests)
}

func TestValidateRefusesBadMaterialsLightsAndPhotonSettings(t *testing.T) {
	nan, inf := math.NaN(), math.Inf(1)
	photons := func(ph *pb.PhotonMapping) func(*pb.Scene) { return func(s *pb.Scene) { s.Photons = ph } }
	lights := func(ls ...*pb.Light) func(*pb.Scene) { return func(s *pb.Scene) { s.Lights = ls } }
	tests := []refusal{
		{"glossy over 1", addMaterial(glossy(rgb(0.5, 0.6, 0), rgb(0.5, 0.5, 0), 10)), "materials[2].glossy.specular.g", "diffuse + specular must be <= 1"},
		{"glossy specular missing", addMaterial(glossy(rgb(0.5, 0.5, 0.5), nil, 10)), "materials[2].glossy.specular", "missing"},
		{"glossy diffuse negative", addMaterial(glossy(rgb(-0.1, 0, 0), rgb(0, 0, 0), 10)), "materials[2].glossy.diffuse.r", "[0, 1], got -0.1"},
		{"glossy exponent 0", addMaterial(glossy(rgb(0, 0, 0), rgb(0, 0, 0), 0)), "materials[2].glossy.exponent", "[1, 100000], got 0"},
		{"glossy exponent too big", addMaterial(glossy(rgb(0, 0, 0), rgb(0, 0, 0), 100001)), "materials[2].glossy.exponent", "got 100001"},
		{"glossy exponent NaN", addMaterial(glossy(rgb(0, 0, 0), rgb(0, 0, 0), nan)), "materials[2].glossy.exponent", "finite"},
		{"mirror over 1", addMaterial(mirror(rgb(1.01, 0, 0))), "materials[2].mirror.reflectance.r", "[0, 1], got 1.01"},
		{"mirror missing", addMaterial(mirror(nil)), "materials[2].mirror.reflectance", "missing"},
		{"ior below 1", addMaterial(dielectric(0.9, nil)), "materials[2].dielectric.ior", "[1, 10], got 0.9"},
		{"ior unset", addMaterial(dielectric(0, nil)), "materials[2].dielectric.ior", "got 0"},
		{"ior too big", addMaterial(dielectric(10.5, nil)), "materials[2].dielectric.ior", "got 10.5"},
		{"ior Inf", addMaterial(dielectric(inf, nil)), "materials[2].dielectric.ior", "finite"},
		{"transmittance over 1", addMaterial(dielectric(1.5, rgb(1, 1, 2))), "materials[2].dielectric.transmittance.b", "[0, 1], got 2"},
		{"eta 0", addMaterial(conductor(rgb(1, 0, 1), rgb(1, 1, 1))), "materials[2].conductor.eta.g", "(0, 100], got 0"},
		{"eta missing", addMaterial(conductor(nil, rgb(1, 1, 1))), "materials[2].conductor.eta", "missing"},
		{"k negative", addMaterial(conductor(rgb(1, 1, 1), rgb(0, 0, -1))), "materials[2].conductor.k.b", "[0, 100], got -1"},
		{"k Inf", addMaterial(conductor(rgb(1, 1, 1), rgb(inf, 0, 0))), "materials[2].conductor.k.r", "finite"},
		{"k NaN", addMaterial(conductor(rgb(1, 1, 1), rgb(0, nan, 0))), "materials[2].conductor.k.g", "finite"},
		{"light without kind", lights(&pb.Light{Name: "x"}), "lights[0]", "exactly one of point, sun, spot must be set"},
		{"point without position", lights(point(nil, rgb(1, 1, 1))), "lights[0].point.position", "missing"},
		{"point NaN position", lights(point(scenetest.V(0, nan, 0), rgb(1, 1, 1))), "lights[0].point.position.y", "finite"},
		{"point negative intensity", lights(point(scenetest.V(0, 1, 0), rgb(1, -1, 1))), "lights[0].point.intensity.g", ">= 0"},
		{"point Inf intensity", lights(point(scenetest.V(0, 1, 0), rgb(inf, 1, 1))), "lights[0].point.intensity.r", "finite"},
		{"point intensity missing", lights(point(scenetest.V(0, 1, 0), nil)), "lights[0].point.intensity", "missing"},
		{"sun zero direction", lights(sun(scenetest.V(0, 0, 0), rgb(1, 1, 1))), "lights[0].sun.direction", "non-zero"},
		{"sun direction missing", lights(sun(nil, rgb(1, 1, 1))), "lights[0].sun.direction", "missing"},
		{"sun negative irradiance", lights(point(scenetest.V(0, 1, 0), rgb(1, 1, 1)), sun(scenetest.V(0, -1, 0), rgb(0, 0, -2))), "lights[1].sun.irradiance.b", ">= 0"},
		{"no light at all", withoutLamp, "lights", "needs a light"},
		{"only dark lights", func(s *pb.Scene) {
			withoutLamp(s)
			s.Lights = []*pb.Light{point(scenetest.V(0, 1, 0), rgb(0, 0, 0)), sun(scenetest.V(0, -1, 0), rgb(0, 0, 0))}
		}, "lights", "needs a light"},
		{"global photons too many", photons(&pb.PhotonMapping{GlobalPhotons: maxPhotons + 1}), "photons.global_photons", "<= 200000000"},
		{"caustic photons too many", photons(&pb.PhotonMapping{CausticPhotons: 1 << 40}), "photons.caustic_photons", "<= 200000000"},
		{"volume photons too many", photons(&pb.PhotonMapping{VolumePhotons: maxPhotons + 1}), "photons.volume_photons", "<= 200000000"},
		{"volume photons in too many shards", photons(&pb.PhotonMapping{VolumePhotons: maxPhotons, PhotonsPerShard: 1000}), "photons.photons_per_shard", "of the volume map's 200000000 photons (photons.volume_photons)"},
		{"shard too small", photons(&pb.PhotonMapping{PhotonsPerShard: 999}), "photons.photons_per_shard", "[1000, 10000000] (0 selects 100000), got 999"},
		{"shard too big", photons(&pb.PhotonMapping{PhotonsPerShard: 10000001}), "photons.photons_per_shard", "got 10000001"},
		{"too many neighbours", photons(&pb.PhotonMapping{GlobalEstimate: &pb.RadianceEstimate{Neighbours: 10001}}), "photons.global_estimate.neighbours", "<= 10000"},
		{"negative radius", photons(&pb.PhotonMapping{CausticEstimate: &pb.RadianceEstimate{MaxRadius: -1}}), "photons.caustic_estimate.max_radius", ">= 0"},
		{"NaN radius", photons(&pb.PhotonMapping{CausticEstimate: &pb.RadianceEstimate{MaxRadius: nan}}), "photons.caustic_estimate.max_radius", "finite"},
		{"Inf radius", photons(&pb.PhotonMapping{GlobalEstimate: &pb.RadianceEstimate{MaxRadius: inf}}), "photons.global_estimate.max_radius", "finite"},
		{"negative volume radius", photons(&pb.PhotonMapping{VolumeEstimate: &pb.RadianceEstimate{MaxRadius: -1}}), "photons.volume_estimate.max_radius", ">= 0"},
		{"cone k below 1", photons(&pb.PhotonMapping{CausticEstimate: &pb.RadianceEstimate{ConeK: 0.5}}), "photons.caustic_estimate.cone_k", "got 0.5"},
		{"cone k negative", photons(&pb.PhotonMapping{CausticEstimate: &pb.RadianceEstimate{ConeK: -2}}), "photons.caustic_estimate.cone_k", "got -2"},
		{"cone k NaN", photons(&pb.PhotonMapping{CausticEstimate: &pb.RadianceEstimate{ConeK: nan}}), "photons.caustic_estimate.cone_k", "finite"},
		{"unknown filter", photons(&pb.PhotonMapping{GlobalEstimate: &pb.RadianceEstimate{Filter: 9}}), "photons.global_estimate.filter", "unknown Filter value 9"},
	}
	expectRefused(t, tests)
}

func TestSurfacesOf(t *testing.T) {
	tests := []struct {
		name   string
		mutate func(*pb.Scene)
		want   scene.Surfaces
	}{
		{"lambert only", func(*pb.Scene) {}, scene.Surfaces{Diffuse: true}},
		{"unused mirror does not count", addMaterial(mirror(rgb(1, 1, 1))), scene.Surfaces{Diffuse: true}},
		{"used mirror", func(s *pb.Scene) {
			s.Materials = append(s.Materials, mirror(rgb(1, 1, 1)))
			s.Shapes[0].Material = "mirror"
		}, scene.Surfaces{Diffuse: true, Specular: true}},
		{"glass and gold only", func(s *pb.Scene) {
			s.Materials = append(s.Materials, dielectric(1.5, nil), conductor(rgb(1, 1, 1), rgb(1, 1, 1)))
			s.Shapes[0].Material, s.Shapes[1].Material = "glass", "gold"
		}, scene.Surfaces{Specular: true}},
		{"glossy is diffuse", func(s *pb.Scene) {
			s.Materials = append(s.Materials, glossy(rgb(0.5, 0.5, 0.5), rgb(0.5, 0.5, 0.5), 20))
			s.Shapes[0].Material, s.Shapes[1].Material = "shiny", "shiny"
		}, scene.Surfaces{Diffuse: true}},
		{"rough principled metal is diffuse", func(s *pb.Scene) {
			s.Materials = append(s.Materials, principled("steel", &pb.Principled{Roughness: 0.5, Metallic: 1}))
			s.Shapes[0].Material, s.Shapes[1].Material = "steel", "steel"
		}, scene.Surfaces{Diffuse: true}},
		{"smooth principled metal is specular", func(s *pb.Scene) {
			threshold := rules.Scene.GetPrincipledSpecularRoughness()
			s.Materials = append(s.Materials, principled("chrome", &pb.Principled{Roughness: math.Nextafter(threshold, 0), Metallic: 1}))
			s.Shapes[0].Material, s.Shapes[1].Material = "chrome", "chrome"
		}, scene.Surfaces{Specular: true}},
		{"smooth principled plastic is both", func(s *pb.Scene) {
			s.Materials = append(s.Materials, principled("plastic", &pb.Principled{Roughness: 0, Metallic: 0}))
			s.Shapes[0].Material, s.Shapes[1].Material = "plastic", "plastic"
		}, scene.Surfaces{Diffuse: true, Specular: true}},
	}
	for _, tt := range tests {
		t.Run(tt.name, func(t *testing.T) {
			if got := scene.SurfacesOf(validated(t, tt.mutate)); got != tt.want {
				t.Errorf("SurfacesOf = %+v, want %+v", got, tt.want)
			}
		})
	}
}

// TestASmoothPrincipledSurfaceGetsACausticMap: the planner's side of the roughness
// threshold the worker also reads (worker/scene/principled_test.cpp): a principled ball
// just smoother than principled_specular_roughness gets the scene a caustic map, one at the
// threshold does not.
func TestASmoothPrincipledSurfaceGetsACausticMap(t *testing.T) {
	threshold := rules.Scene.GetPrincipledSpecularRoughness()
	for _, tt := range []struct {
		roughness float64
		caustic   bool
	}{{math.Nextafter(threshold, 0), true}, {threshold, false}} {
		s := scenetest.Valid(8, 8)
		s.Materials = append(s.Materials, principled("ball", &pb.Principled{Roughness: tt.roughness, Metallic: 1}))
		s.Shapes[0].Material = "ball"
		caustic := false
		for _, m := range scene.PhotonMaps(s) {
			caustic = caustic || m.Kind == pb.PhotonMapKind_PHOTON_MAP_KIND_CAUSTIC
		}
		if caustic != tt.caustic {
			t.Errorf("roughness %v: caustic map %v, want %v", tt.roughness, caustic, tt.caustic)
		}
	}
}
