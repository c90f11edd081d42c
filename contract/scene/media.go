package scene

import (
	"fmt"
	"math"
	"slices"

	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

// Medium is one medium of a scene as the planner weighs it.
type Medium struct {
	// Label names it for people: "the scene's medium", `shapes[3] ("box")'s interior
	// medium`.
	Label  string
	Medium *pb.Medium
	// Dark says why no light can reach it, "" when light may.
	Dark string
}

// Media returns s's media: the medium filling the scene, if set, then every shape's
// interior medium in shape order, each with why no light reaches it, if none can.
//
// The scene's medium is always lit (every valid scene has a light, and lights sit in it).
// A shape's interior medium is entered only by crossing the shape's surface from its
// front to its back (docs/media.md), which only a transmitting surface lets light do; so
// it is dark when the planner can tell that the shape's surface transmits nothing and no
// light is inside it. That is decided conservatively, erring towards "lit": a shape of a
// mesh file or an instance is never dark (its vertices are not in the scene), nor one with
// a dielectric, an alpha-masked or a normal-mapped material (shading normals may turn a
// reflection across the surface), nor one whose bounding ball holds a point or spot light
// or meets an emitter's (the shape itself emitting included).
func Media(s *pb.Scene) []Medium {
	var out []Medium
	if m := s.GetMedium(); m != nil {
		out = append(out, Medium{Label: "the scene's medium", Medium: m})
	}
	materials := ShapeMaterials(s)
	for i, sh := range s.GetShapes() {
		m := sh.GetInteriorMedium()
		if m == nil {
			continue
		}
		label := index("shapes", i)
		if sh.GetName() != "" {
			label += fmt.Sprintf(" (%q)", sh.GetName())
		}
		out = append(out, Medium{Label: label + "'s interior medium", Medium: m, Dark: darkInside(s, materials, i)})
	}
	return out
}

// darkInside says why no light reaches inside shape i, or "" if light may.
func darkInside(s *pb.Scene, materials [][]*pb.Material, i int) string {
	if slices.ContainsFunc(materials[i], func(m *pb.Material) bool { return !keepsLightOut(m) }) {
		return ""
	}
	c, r, known := shapeBall(s.GetShapes()[i])
	if !known || anyLightInside(s, materials, c, r) {
		return ""
	}
	return "no light reaches it: its surface transmits none (no dielectric, cut-out or normal map) and no light is inside it"
}

// keepsLightOut reports whether light cannot cross a surface of m from its front to its
// back: it reflects, absorbs or emits, but transmits nothing, and its shading normal is
// its geometric one. It panics for a kind it does not know, so that a new material cannot
// silently count as opaque.
func keepsLightOut(m *pb.Material) bool {
	switch k := m.GetKind().(type) {
	case *pb.Material_Lambert, *pb.Material_Glossy, *pb.Material_Mirror, *pb.Material_Conductor, *pb.Material_Emissive:
		return true
	case *pb.Material_Dielectric:
		return false
	case *pb.Material_Principled:
		return k.Principled.GetNormalTexture() == nil && k.Principled.GetAlphaMode() != pb.AlphaMode_ALPHA_MODE_MASK
	default:
		panic(fmt.Sprintf("scene: keepsLightOut does not know material kind %T", k))
	}
}

// scatters reports whether light can scatter in m: sigma_s positive in some channel, or an
// albedo positive in some channel with a positive density (a grid's density scale is
// positive; its file's densities are not looked at). A medium that only absorbs
// attenuates rays but stores no volume photon.
func scatters(m *pb.Medium) bool {
	if a := m.GetAlbedo(); a != nil {
		return a.GetDensity() > 0 && positive(a.GetAlbedo())
	}
	if g := m.GetGrid(); g != nil {
		return positive(g.GetAlbedo())
	}
	return positive(m.GetSigma().GetSigmaS())
}

// Scatters reports whether light can scatter in the medium (its sigma_s is positive
// somewhere).
func (m Medium) Scatters() bool { return scatters(m.Medium) }

// PathTraced reports whether m's multiple scattering is path traced rather than read from
// the volume photon map: its Henyey-Greenstein |g| is at least the contract's
// path_traced_media_min_abs_g (rules.Scene), a lobe too narrow for k photons to weigh.
func PathTraced(m *pb.Medium) bool {
	return math.Abs(m.GetG()) >= rules.Scene.GetPathTracedMediaMinAbsG()
}

// litScattering reports whether some medium of s that light can reach scatters it and
// satisfies also.
func litScattering(s *pb.Scene, also func(*pb.Medium) bool) bool {
	return slices.ContainsFunc(Media(s), func(m Medium) bool { return m.Dark == "" && m.Scatters() && also(m.Medium) })
}

// MediaScatter reports whether some medium of s that light can reach scatters it.
func MediaScatter(s *pb.Scene) bool {
	return litScattering(s, func(*pb.Medium) bool { return true })
}

// MediaPathTraced reports whether some medium of s that light reaches and that scatters
// it is path traced.
func MediaPathTraced(s *pb.Scene) bool { return litScattering(s, PathTraced) }

// VolumeMapNeeded reports whether some medium of s that light reaches scatters it and is
// not path traced, which decides whether s gets a volume map.
func VolumeMapNeeded(s *pb.Scene) bool {
	return litScattering(s, func(m *pb.Medium) bool { return !PathTraced(m) })
}
