package scene

import (
	"math"

	pb "photonfarm/proto/renderfarm/v1"
)

// validateSurface checks the reflecting materials beyond Lambert: glossy, mirror,
// dielectric and conductor (scene.proto states each one's ranges).
func validateSurface(p string, m *pb.Material) error {
	switch k := m.GetKind().(type) {
	case *pb.Material_Glossy:
		return validateGlossy(p+".glossy", k.Glossy)
	case *pb.Material_Mirror:
		return checkColor(p+".mirror.reflectance", k.Mirror.GetReflectance(), 1)
	case *pb.Material_Dielectric:
		return validateDielectric(p+".dielectric", k.Dielectric)
	case *pb.Material_Conductor:
		return validateConductor(p+".conductor", k.Conductor)
	}
	return fe(p, "exactly one kind (lambert, emissive, glossy, mirror, dielectric, conductor) must be set")
}

func validateGlossy(p string, g *pb.Glossy) error {
	if err := checkColor(p+".diffuse", g.GetDiffuse(), 1); err != nil {
		return err
	}
	if err := checkColor(p+".specular", g.GetSpecular(), 1); err != nil {
		return err
	}
	d, s := g.GetDiffuse(), g.GetSpecular()
	for _, c := range []struct {
		n    string
		d, s float64
	}{{"r", d.GetR(), s.GetR()}, {"g", d.GetG(), s.GetG()}, {"b", d.GetB(), s.GetB()}} {
		if c.d+c.s > 1 {
			return fe(p+".specular."+c.n, "diffuse + specular must be <= 1 (energy conservation), got %s + %s",
				fmtNum(c.d), fmtNum(c.s))
		}
	}
	e := g.GetExponent()
	if err := checkFinite(p+".exponent", e); err != nil {
		return err
	}
	if e < MinGlossyExponent || e > MaxGlossyExponent {
		return fe(p+".exponent", "must be in [%s, %s], got %s", fmtNum(MinGlossyExponent), fmtNum(MaxGlossyExponent), fmtNum(e))
	}
	return nil
}

func validateDielectric(p string, d *pb.Dielectric) error {
	ior := d.GetIor()
	if err := checkFinite(p+".ior", ior); err != nil {
		return err
	}
	if ior < MinIOR || ior > MaxIOR {
		return fe(p+".ior", "must be in [%s, %s], got %s", fmtNum(MinIOR), fmtNum(MaxIOR), fmtNum(ior))
	}
	if t := d.GetTransmittance(); t != nil {
		return checkColor(p+".transmittance", t, 1)
	}
	return nil
}

func validateConductor(p string, c *pb.Conductor) error {
	eta := c.GetEta()
	if err := checkColor(p+".eta", eta, math.Inf(1)); err != nil {
		return err
	}
	for _, comp := range []struct {
		n string
		v float64
	}{{"r", eta.GetR()}, {"g", eta.GetG()}, {"b", eta.GetB()}} {
		if comp.v <= 0 {
			return fe(p+".eta."+comp.n, "must be > 0, got %s", fmtNum(comp.v))
		}
	}
	return checkColor(p+".k", c.GetK(), math.Inf(1))
}
