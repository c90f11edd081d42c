package scene

import (
	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

// Names and the references to them: shapes and mesh parts name materials, instances name
// meshes, materials and the environment name textures.

// checkNames: materials, meshes and textures are named by reference, so no two of a kind
// may share a name (materials[i].name, then meshes[i].name, then textures[i].name).
func checkNames(s *pb.Scene) *FieldError {
	for _, kind := range []struct {
		list, what string
		names      []string
	}{
		{"materials", "material", names(s.GetMaterials())},
		{"meshes", "mesh", names(s.GetMeshes())},
		{"textures", "texture", names(s.GetTextures())},
	} {
		first := make(map[string]int, len(kind.names))
		for i, name := range kind.names {
			if j, dup := first[name]; dup {
				return rules.Errorf(index(kind.list, i)+".name", "duplicate %s name %q (also %s)", kind.what, rules.Truncate(name, 80), index(kind.list, j))
			}
			first[name] = i
		}
	}
	return nil
}

type named interface{ GetName() string }

// byName indexes a list by name.
func byName[T named](list []T) map[string]T {
	m := make(map[string]T, len(list))
	for _, x := range list {
		m[x.GetName()] = x
	}
	return m
}

func names[T named](list []T) []string {
	out := make([]string, len(list))
	for i, x := range list {
		out[i] = x.GetName()
	}
	return out
}

// checkShapeMaterials: every shape but an instance names a material; an instance names a
// mesh and no material, its mesh's parts naming theirs (shapes[i].material, then
// shapes[i].instance.mesh).
func checkShapeMaterials(s *pb.Scene) *FieldError {
	materials, meshes := byName(s.GetMaterials()), byName(s.GetMeshes())
	for i, sh := range s.GetShapes() {
		p := index("shapes", i)
		inst := sh.GetInstance()
		switch _, ok := materials[sh.GetMaterial()]; {
		case inst != nil && sh.GetMaterial() != "":
			return rules.Errorf(p+".material", "must be empty for an instance, whose mesh's parts name their materials; got %q", rules.Truncate(sh.GetMaterial(), 80))
		case inst == nil && sh.GetMaterial() == "":
			return rules.Errorf(p+".material", "missing; a shape names one of the scene's materials")
		case inst == nil && !ok:
			return rules.Errorf(p+".material", "no material named %q", rules.Truncate(sh.GetMaterial(), 80))
		}
		if _, ok := meshes[inst.GetMesh()]; inst != nil && !ok {
			return rules.Errorf(p+".instance.mesh", "no mesh named %q", rules.Truncate(inst.GetMesh(), 80))
		}
	}
	return nil
}

// checkPartMaterials: every mesh part's material exists (meshes[i].parts[j].material).
func checkPartMaterials(s *pb.Scene) *FieldError {
	materials := byName(s.GetMaterials())
	for i, m := range s.GetMeshes() {
		for j, part := range m.GetParts() {
			if _, ok := materials[part.GetMaterial()]; !ok {
				return rules.Errorf(index(index("meshes", i)+".parts", j)+".material", "no material named %q", rules.Truncate(part.GetMaterial(), 80))
			}
		}
	}
	return nil
}

// checkTextureRefs: every texture a material or the environment reads exists
// (materials[i].principled.base_color_texture.texture, ..., environment.map.texture).
func checkTextureRefs(s *pb.Scene) *FieldError {
	textures := byName(s.GetTextures())
	for _, ref := range TextureRefs(s) {
		if _, ok := textures[ref.Ref.GetTexture()]; !ok {
			return rules.Errorf(ref.Field+".texture", "no texture named %q", rules.Truncate(ref.Ref.GetTexture(), 80))
		}
	}
	return nil
}

// TextureRef is a place where a scene reads a texture.
type TextureRef struct {
	// Field names the reference: "materials[2].principled.base_color_texture", "environment.map".
	Field string
	Ref   *pb.TextureRef
}

// TextureRefs lists the texture references of s that are set, in field order: each
// principled material's base colour, metallic-roughness, normal and emission textures, then
// the environment's map.
func TextureRefs(s *pb.Scene) []TextureRef {
	var refs []TextureRef
	add := func(field string, ref *pb.TextureRef) {
		if ref != nil {
			refs = append(refs, TextureRef{Field: field, Ref: ref})
		}
	}
	for i, m := range s.GetMaterials() {
		if p := m.GetPrincipled(); p != nil {
			at := index("materials", i) + ".principled."
			add(at+"base_color_texture", p.GetBaseColorTexture())
			add(at+"metallic_roughness_texture", p.GetMetallicRoughnessTexture())
			add(at+"normal_texture", p.GetNormalTexture())
			add(at+"emission_texture", p.GetEmissionTexture())
		}
	}
	add("environment.map", s.GetEnvironment().GetMap())
	return refs
}

// ShapeMaterials returns the materials each shape of s uses, by shape index: its own, or
// for an instance those of its mesh's parts, in part order. s must have passed the
// reference rules of Validate (checkShapeMaterials, checkPartMaterials).
func ShapeMaterials(s *pb.Scene) [][]*pb.Material {
	materials, meshes := byName(s.GetMaterials()), byName(s.GetMeshes())
	out := make([][]*pb.Material, len(s.GetShapes()))
	for i, sh := range s.GetShapes() {
		inst := sh.GetInstance()
		if inst == nil {
			out[i] = []*pb.Material{materials[sh.GetMaterial()]}
			continue
		}
		for _, part := range meshes[inst.GetMesh()].GetParts() {
			out[i] = append(out[i], materials[part.GetMaterial()])
		}
	}
	return out
}

// anyMaterial reports whether f holds for one of ms.
func anyMaterial(ms []*pb.Material, f func(*pb.Material) bool) bool {
	for _, m := range ms {
		if f(m) {
			return true
		}
	}
	return false
}
