package scene

import pb "photonfarm/proto/renderfarm/v1"

// Surfaces says which kinds of surface a scene's shapes have, which decides the photon maps
// it needs: a global map if any shape reflects diffusely (Lambert, glossy with its diffuse
// lobe, principled), a caustic map if any is specular (mirror, dielectric, conductor, a
// principled material smoother than the contract's principled_specular_roughness).
// Materials no shape uses do not count (an instance uses its mesh's parts'); emissive
// shapes reflect nothing.
type Surfaces struct {
	Diffuse  bool
	Specular bool
}

// SurfacesOf classifies the materials used by s's shapes. s must have passed Validate.
func SurfacesOf(s *pb.Scene) Surfaces {
	var out Surfaces
	for _, materials := range ShapeMaterials(s) {
		for _, m := range materials {
			c := CapabilitiesOf(m)
			out.Diffuse = out.Diffuse || c.Diffuse
			out.Specular = out.Specular || c.Specular
		}
	}
	return out
}
