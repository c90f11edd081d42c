package scene

import (
	"fmt"

	pb "photonfarm/proto/renderfarm/v1"
)

// Capabilities is what a kind of material does to light: the one place the coordinator
// decides it (the worker's is MaterialCapabilities, worker/scene/materials.h). The photon
// maps a scene gets, and the interreflection analysis, ask this instead of switching over
// material kinds themselves.
type Capabilities struct {
	// Diffuse: reflects non-specularly, so direct light and photon estimates apply where it
	// is hit (Lambert; glossy, which has a diffuse lobe).
	Diffuse bool
	// Specular: its BSDF is a delta function (mirror, dielectric, conductor); it carries
	// caustics and stores no photons.
	Specular bool
	// Emissive: an area light (whether it emits depends on its radiance).
	Emissive bool
}

// CapabilitiesOf returns the capabilities of m's kind. It panics for a kind it does not
// know, so that a new material cannot silently count as nothing; TestEveryMaterialKindHas-
// Capabilities fails until it is added here.
func CapabilitiesOf(m *pb.Material) Capabilities {
	switch k := m.GetKind().(type) {
	case *pb.Material_Lambert, *pb.Material_Glossy:
		return Capabilities{Diffuse: true}
	case *pb.Material_Mirror, *pb.Material_Dielectric, *pb.Material_Conductor:
		return Capabilities{Specular: true}
	case *pb.Material_Emissive:
		return Capabilities{Emissive: true}
	case *pb.Material_Principled:
		// Its diffuse base; the principled material's own rules (a nearly smooth surface is
		// specular) refine this.
		return Capabilities{Diffuse: true}
	default:
		panic(fmt.Sprintf("scene: CapabilitiesOf does not know material kind %T", k))
	}
}
