package scene

import (
	"fmt"

	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

// Capabilities is what a kind of material does to light: the one place the coordinator
// decides it (the worker's is MaterialCapabilities, worker/scene/materials.h). The photon
// maps a scene gets, and the interreflection analysis, ask this instead of switching over
// material kinds themselves.
//
// A principled material can have several: its microfacet lobe is specular when its roughness
// factor is below the contract's principled_specular_roughness (rules.Scene), and it is
// diffuse unless that lobe is all it has (specular, fully metallic, no texture that could
// lower metallic); it is emissive with a positive emission.
type Capabilities struct {
	// Diffuse: reflects non-specularly, so direct light and photon estimates apply where it
	// is hit (Lambert; glossy, which has a diffuse lobe; principled).
	Diffuse bool
	// Specular: its BSDF is a delta function (mirror, dielectric, conductor) or a lobe that
	// counts as one (a smooth principled material); it carries caustics and stores no
	// photons.
	Specular bool
	// Emissive: an area light (whether an emissive material emits depends on its radiance;
	// one with a reflectance is Diffuse too).
	Emissive bool
}

// CapabilitiesOf returns the capabilities of m's kind. It panics for a kind it does not
// know, so that a new material cannot silently count as nothing; TestEveryMaterialKindHas-
// Capabilities fails until it is added here. The worker decides the same
// (MaterialCapabilities, worker/scene/materials.h; the shared vectors hold both to it).
func CapabilitiesOf(m *pb.Material) Capabilities {
	switch k := m.GetKind().(type) {
	case *pb.Material_Principled:
		return principledCapabilities(k.Principled)
	case *pb.Material_Lambert, *pb.Material_Glossy:
		return Capabilities{Diffuse: true}
	case *pb.Material_Mirror, *pb.Material_Dielectric, *pb.Material_Conductor:
		return Capabilities{Specular: true}
	case *pb.Material_Emissive:
		// It reflects as a Lambertian surface where it has a reflectance.
		return Capabilities{Emissive: true, Diffuse: positive(k.Emissive.GetReflectance())}
	default:
		panic(fmt.Sprintf("scene: CapabilitiesOf does not know material kind %T", k))
	}
}

// PrincipledIsSpecular says whether a principled material's microfacet lobe counts as
// specular: its roughness factor is below the contract's threshold (textures can only lower
// roughness, so they never make a specular material glossy; a textured roughness below the
// threshold on a glossy material is clamped to it by the worker).
func PrincipledIsSpecular(p *pb.Principled) bool {
	return p.GetRoughness() < rules.Scene.GetPrincipledSpecularRoughness()
}

func principledCapabilities(p *pb.Principled) Capabilities {
	specular := PrincipledIsSpecular(p)
	onlySpecular := specular && p.GetMetallic() == 1 && p.GetMetallicRoughnessTexture() == nil
	return Capabilities{Diffuse: !onlySpecular, Specular: specular, Emissive: positive(p.GetEmission())}
}
