package scene

import (
	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

// checkMaterialNames: shapes name materials, so no two may share a name
// (materials[i].name).
func checkMaterialNames(s *pb.Scene) *FieldError {
	first := make(map[string]int, len(s.GetMaterials()))
	for i, m := range s.GetMaterials() {
		if j, dup := first[m.GetName()]; dup {
			return rules.Errorf(index("materials", i)+".name", "duplicate material name %q (also materials[%d])", rules.Truncate(m.GetName(), 80), j)
		}
		first[m.GetName()] = i
	}
	return nil
}

// checkShapeMaterials: every shape's material exists (shapes[i].material).
func checkShapeMaterials(s *pb.Scene) *FieldError {
	names := materialsByName(s)
	for i, sh := range s.GetShapes() {
		if _, ok := names[sh.GetMaterial()]; !ok {
			return rules.Errorf(index("shapes", i)+".material", "no material named %q", rules.Truncate(sh.GetMaterial(), 80))
		}
	}
	return nil
}

// checkGlossyEnergy: a glossy surface reflects no more than it receives
// (materials[i].glossy.specular.r, .g or .b).
func checkGlossyEnergy(s *pb.Scene) *FieldError {
	for i, m := range s.GetMaterials() {
		g := m.GetGlossy()
		if g == nil {
			continue
		}
		d, sp := g.GetDiffuse(), g.GetSpecular()
		for _, c := range []struct {
			name          string
			diffuse, spec float64
		}{{"r", d.GetR(), sp.GetR()}, {"g", d.GetG(), sp.GetG()}, {"b", d.GetB(), sp.GetB()}} {
			if c.diffuse+c.spec > 1 {
				return rules.Errorf(index("materials", i)+".glossy.specular."+c.name,
					"diffuse + specular must be <= 1 (energy conservation), got %s + %s", rules.Number(c.diffuse), rules.Number(c.spec))
			}
		}
	}
	return nil
}

// materialsByName indexes s's materials by name.
func materialsByName(s *pb.Scene) map[string]*pb.Material {
	byName := make(map[string]*pb.Material, len(s.GetMaterials()))
	for _, m := range s.GetMaterials() {
		byName[m.GetName()] = m
	}
	return byName
}
