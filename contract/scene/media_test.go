package scene_test

import (
	"math"
	"slices"
	"strings"
	"testing"

	"photonfarm/contract/rules"
	"photonfarm/contract/scene"
	"photonfarm/contract/scene/scenetest"
	pb "photonfarm/proto/renderfarm/v1"
)

func sigmaMedium(sigmaA, sigmaS *pb.Color) *pb.Medium {
	return &pb.Medium{Coefficients: &pb.Medium_Sigma{Sigma: &pb.MediumCoefficients{SigmaA: sigmaA, SigmaS: sigmaS}}}
}

func albedoMedium(albedo *pb.Color, density float64) *pb.Medium {
	return &pb.Medium{Coefficients: &pb.Medium_Albedo{Albedo: &pb.MediumAlbedo{Albedo: albedo, Density: density}}}
}

// withG sets m's Henyey-Greenstein asymmetry.
func withG(m *pb.Medium, g float64) *pb.Medium {
	m.G = g
	return m
}

// gridMedium is smoke from a grid file (not looked at here) of albedo 0.9 and asymmetry g.
func gridMedium(g float64) *pb.Medium {
	return &pb.Medium{G: g, Coefficients: &pb.Medium_Grid{Grid: &pb.MediumGrid{Digest: "sha256:" + strings.Repeat("0", 64), Albedo: rgb(0.9, 0.9, 0.9)}}}
}

// pathTracedG is the contract's path_traced_media_min_abs_g.
var pathTracedG = rules.Scene.GetPathTracedMediaMinAbsG()

// TestPhotonMapsGetAVolumeMapWhereAMediumScatters: the volume map comes after the global and
// caustic maps, and only when the scene's medium or a shape's interior medium scatters
// light in some channel and light can reach it; a medium that only absorbs gets none, nor
// one inside an opaque ball with no light inside.
func TestPhotonMapsGetAVolumeMapWhereAMediumScatters(t *testing.T) {
	const (
		global  = pb.PhotonMapKind_PHOTON_MAP_KIND_GLOBAL
		caustic = pb.PhotonMapKind_PHOTON_MAP_KIND_CAUSTIC
		volume  = pb.PhotonMapKind_PHOTON_MAP_KIND_VOLUME
	)
	fog := func(m *pb.Medium) func(*pb.Scene) { return func(s *pb.Scene) { s.Medium = m } }
	tests := []struct {
		name   string
		mutate func(*pb.Scene)
		want   []pb.PhotonMapKind
	}{
		{"no medium", func(*pb.Scene) {}, []pb.PhotonMapKind{global}},
		{"fog that only absorbs", fog(sigmaMedium(rgb(0.1, 0.1, 0.1), rgb(0, 0, 0))), []pb.PhotonMapKind{global}},
		{"fog scattering blue only", fog(sigmaMedium(rgb(0, 0, 0), rgb(0, 0, 0.01))), []pb.PhotonMapKind{global, volume}},
		{"albedo without density", fog(albedoMedium(rgb(0.9, 0.9, 0.9), 0)), []pb.PhotonMapKind{global}},
		{"black albedo with density", fog(albedoMedium(rgb(0, 0, 0), 2)), []pb.PhotonMapKind{global}},
		{"a murky glass ball scatters", func(s *pb.Scene) {
			addMaterial(dielectric(1.5, nil))(s)
			s.Shapes[0].Material = "glass"
			s.Shapes[0].InteriorMedium = albedoMedium(rgb(0, 0.5, 0), 2)
		}, []pb.PhotonMapKind{global, caustic, volume}},
		{"smoke in a closed diffuse ball is dark", func(s *pb.Scene) { s.Shapes[0].InteriorMedium = albedoMedium(rgb(0, 0.5, 0), 2) }, []pb.PhotonMapKind{global}},
		{"one scattering medium among absorbing ones", func(s *pb.Scene) {
			s.Medium = sigmaMedium(rgb(0.1, 0.1, 0.1), rgb(0, 0, 0))
			s.Shapes[0].InteriorMedium = albedoMedium(rgb(0.9, 0.9, 0.9), 0)
			s.Shapes[1].InteriorMedium = sigmaMedium(rgb(0, 0, 0), rgb(0.2, 0, 0)) // the floor, a quad, has a lamp above it
		}, []pb.PhotonMapKind{global, volume}},
		// At |g| >= path_traced_media_min_abs_g a medium's multiple scattering is path
		// traced: it needs no volume map, and gets one only beside a medium that does.
		{"forward-scattering fog at the threshold", fog(withG(albedoMedium(rgb(0.9, 0.9, 0.9), 2), pathTracedG)), []pb.PhotonMapKind{global}},
		{"backward-scattering fog", fog(withG(albedoMedium(rgb(0.9, 0.9, 0.9), 2), -0.999)), []pb.PhotonMapKind{global}},
		{"fog just below the threshold", fog(withG(albedoMedium(rgb(0.9, 0.9, 0.9), 2), math.Nextafter(pathTracedG, 0))), []pb.PhotonMapKind{global, volume}},
		{"forward-scattering fog around an isotropic murky glass ball", func(s *pb.Scene) {
			s.Medium = withG(albedoMedium(rgb(0.9, 0.9, 0.9), 2), 0.999)
			addMaterial(dielectric(1.5, nil))(s)
			s.Shapes[0].Material = "glass"
			s.Shapes[0].InteriorMedium = albedoMedium(rgb(0, 0.5, 0), 2)
		}, []pb.PhotonMapKind{global, caustic, volume}},
		// A medium no light reaches needs no volume map, whatever its g.
		{"forward-scattering fog around isotropic smoke in a closed diffuse ball", func(s *pb.Scene) {
			s.Medium = withG(albedoMedium(rgb(0.9, 0.9, 0.9), 2), 0.999)
			s.Shapes[0].InteriorMedium = albedoMedium(rgb(0, 0.5, 0), 2)
		}, []pb.PhotonMapKind{global}},
		// Grids by their albedo and g alike.
		{"grid smoke", fog(gridMedium(0)), []pb.PhotonMapKind{global, volume}},
		{"forward-scattering grid smoke", fog(gridMedium(0.95)), []pb.PhotonMapKind{global}},
		{"plan order: global, caustic, volume", func(s *pb.Scene) {
			addMaterial(mirror(rgb(1, 1, 1)))(s)
			s.Shapes[0].Material = "mirror"
			s.Medium = sigmaMedium(rgb(0, 0, 0), rgb(0.05, 0.05, 0.05))
			s.Photons = &pb.PhotonMapping{VolumePhotons: 3000}
		}, []pb.PhotonMapKind{global, caustic, volume}},
	}
	for _, tt := range tests {
		t.Run(tt.name, func(t *testing.T) {
			s := validated(t, tt.mutate)
			var got []pb.PhotonMapKind
			for _, m := range scene.PhotonMaps(s) {
				got = append(got, m.Kind)
				if want := scene.VolumePhotons(s); m.Kind == volume && m.Photons != want {
					t.Errorf("volume map of %d photon paths, want photons.volume_photons' %d", m.Photons, want)
				}
			}
			if !slices.Equal(got, tt.want) {
				t.Errorf("PhotonMaps = %v, want %v", got, tt.want)
			}
		})
	}
}

func TestVolumePhotonsDefaultsTo200000(t *testing.T) {
	for _, tt := range []struct {
		set, want uint64
	}{{0, 200000}, {1, 1}, {50000000, 50000000}} {
		s := validated(t, func(s *pb.Scene) { s.Photons = &pb.PhotonMapping{VolumePhotons: tt.set} })
		if got := scene.VolumePhotons(s); got != tt.want {
			t.Errorf("volume_photons %d: VolumePhotons = %d, want %d", tt.set, got, tt.want)
		}
	}
}

// TestMediaInsideOpaqueShapesAreDarkOnlyWhenThePlannerCanTell: a shape's interior medium
// is dark only when its surface transmits nothing, its shading normals are its geometric
// ones, its bounds are known and no light is inside; everything else errs towards lit.
func TestMediaInsideOpaqueShapesAreDarkOnlyWhenThePlannerCanTell(t *testing.T) {
	smoke := albedoMedium(rgb(0.9, 0.9, 0.9), 1)
	principled := func(p *pb.Principled) func(*pb.Scene) {
		return func(s *pb.Scene) {
			s.Textures = []*pb.Texture{{Name: "bumps", Digest: "sha256:" + strings.Repeat("0", 64)}}
			addMaterial(&pb.Material{Name: "paint", Kind: &pb.Material_Principled{Principled: p}})(s)
			s.Shapes[0].Material = "paint"
		}
	}
	tests := []struct {
		name   string
		mutate func(*pb.Scene)
		dark   bool
	}{
		{"a diffuse ball, the lamp above it", func(*pb.Scene) {}, true},
		{"a mirror ball", func(s *pb.Scene) { addMaterial(mirror(rgb(1, 1, 1)))(s); s.Shapes[0].Material = "mirror" }, true},
		{"a plain principled ball", principled(&pb.Principled{BaseColor: rgb(0.5, 0.5, 0.5), Roughness: 0.5}), true},
		{"a glass ball", func(s *pb.Scene) { addMaterial(dielectric(1.5, nil))(s); s.Shapes[0].Material = "glass" }, false},
		{"a normal-mapped ball", principled(&pb.Principled{Roughness: 0.5, NormalTexture: &pb.TextureRef{Texture: "bumps"}}), false},
		{"a cut-out ball", principled(&pb.Principled{Roughness: 0.5, AlphaMode: pb.AlphaMode_ALPHA_MODE_MASK, Transparency: 0.5}), false},
		{"a point light inside", func(s *pb.Scene) { s.Lights = append(s.Lights, point(scenetest.V(0, 1.5, 0), rgb(1, 1, 1))) }, false},
		{"the lamp lowered into the ball", func(s *pb.Scene) { s.Shapes[2].GetQuad().Origin = scenetest.V(-0.5, 1.2, 0.5) }, false},
		{"the ball itself glows", func(s *pb.Scene) { s.Shapes[0].Material = "light" }, false},
		{"a mesh file's shape", func(s *pb.Scene) {
			s.Shapes[0].Geometry = &pb.Shape_Mesh{Mesh: &pb.MeshFile{Digest: "sha256:" + strings.Repeat("0", 64)}}
		}, false},
	}
	for _, tt := range tests {
		t.Run(tt.name, func(t *testing.T) {
			s := validated(t, func(s *pb.Scene) {
				tt.mutate(s)
				s.Shapes[0].InteriorMedium = smoke
			})
			media := scene.Media(s)
			if len(media) != 1 || media[0].Label != `shapes[0] ("ball")'s interior medium` {
				t.Fatalf("Media = %+v, want the ball's interior medium", media)
			}
			if got := media[0].Dark != ""; got != tt.dark {
				t.Errorf("dark %v (%q), want %v", got, media[0].Dark, tt.dark)
			}
			if scene.MediaScatter(s) == tt.dark || scene.VolumeMapNeeded(s) == tt.dark {
				t.Errorf("MediaScatter %v, VolumeMapNeeded %v for a medium dark %v", scene.MediaScatter(s), scene.VolumeMapNeeded(s), tt.dark)
			}
		})
	}
}

// TestHittableLightsAreThoseARayCanMeet: single scattering takes phase-function samples
// only where some light has a surface or a solid angle a ray can meet.
func TestHittableLightsAreThoseARayCanMeet(t *testing.T) {
	withoutLamp := func(s *pb.Scene) { s.Shapes = s.Shapes[:len(s.Shapes)-1] }
	light := func(l *pb.Light) func(*pb.Scene) {
		return func(s *pb.Scene) {
			withoutLamp(s)
			s.Lights = []*pb.Light{l}
		}
	}
	sun := func(degrees float64) *pb.Light {
		return &pb.Light{Kind: &pb.Light_Sun{Sun: &pb.SunLight{Direction: scenetest.V(0, -1, 0), Irradiance: rgb(1, 1, 1), AngularDiameterDegrees: degrees}}}
	}
	for _, tt := range []struct {
		name   string
		mutate func(*pb.Scene)
		want   bool
	}{
		{"an emissive quad", func(*pb.Scene) {}, true},
		{"a point light", light(&pb.Light{Kind: &pb.Light_Point{Point: &pb.PointLight{Position: scenetest.V(0, 2, 0), Intensity: rgb(1, 1, 1)}}}), false},
		{"a sun without a disc", light(sun(0)), false},
		{"a sun with a disc", light(sun(0.5)), true},
		{"a constant sky", func(s *pb.Scene) {
			light(sun(0))(s)
			s.Environment = &pb.Environment{Radiance: rgb(0.1, 0.2, 0.3)}
		}, true},
	} {
		t.Run(tt.name, func(t *testing.T) {
			if got := scene.HittableLights(validated(t, tt.mutate)); got != tt.want {
				t.Errorf("HittableLights = %v, want %v", got, tt.want)
			}
		})
	}
}
