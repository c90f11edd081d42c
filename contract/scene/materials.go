package scene

import (
	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

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
