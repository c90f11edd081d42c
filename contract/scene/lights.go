package scene

import (
	"fmt"
	"slices"

	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

// checkSomeLight: something emits (lights): a point, spot or sun light with a positive
// component, a shape (or an instanced mesh part) whose material emits, or an environment
// that is not black.
func checkSomeLight(s *pb.Scene) *FieldError {
	for _, l := range s.GetLights() {
		if positive(lightPower(l)) {
			return nil
		}
	}
	for _, materials := range ShapeMaterials(s) {
		if anyMaterial(materials, Emits) {
			return nil
		}
	}
	if EnvironmentLights(s) {
		return nil
	}
	return rules.Errorf("lights", "the scene needs a light: a point, spot or sun light with a positive component, "+
		"a shape whose material emits (emissive with a positive radiance, or principled with a positive emission), "+
		"or an environment that is not black")
}

// lightPower is what makes a light without geometry shine: its intensity or irradiance.
func lightPower(l *pb.Light) *pb.Color {
	switch k := l.GetKind().(type) {
	case *pb.Light_Point:
		return k.Point.GetIntensity()
	case *pb.Light_Spot:
		return k.Spot.GetIntensity()
	case *pb.Light_Sun:
		return k.Sun.GetIrradiance()
	default:
		panic(fmt.Sprintf("scene: lightPower does not know light %T", k))
	}
}

// Emits reports whether a material emits light: emissive with a positive radiance, or
// principled with a positive emission.
func Emits(m *pb.Material) bool {
	return positive(m.GetEmissive().GetRadiance()) || positive(m.GetPrincipled().GetEmission())
}

// EnvironmentLights reports whether s's environment is not black: a positive radiance, or
// a map with the radiance unset (which multiplies the map by 1). A map's pixels are not
// inspected here.
func EnvironmentLights(s *pb.Scene) bool {
	env := s.GetEnvironment()
	if env.GetRadiance() == nil {
		return env.GetMap() != nil
	}
	return positive(env.GetRadiance())
}

// HittableLights reports whether some light of s can be met by a ray (single scattering's
// phase-function samples find it): an emissive shape or mesh part, an environment that is
// not black, or a sun with a disc. Point and spot lights and suns without a disc cannot.
func HittableLights(s *pb.Scene) bool {
	if EnvironmentLights(s) {
		return true
	}
	for _, l := range s.GetLights() {
		if l.GetSun().GetAngularDiameterDegrees() > 0 {
			return true
		}
	}
	for _, materials := range ShapeMaterials(s) {
		if slices.ContainsFunc(materials, Emits) {
			return true
		}
	}
	return false
}

// checkLightShapes: a sun or spot light shines from somewhere (lights[i].sun.direction,
// lights[i].spot.direction) and a spot's inner cone lies inside its outer one
// (lights[i].spot.inner_cone_degrees).
func checkLightShapes(s *pb.Scene) *FieldError {
	for i, l := range s.GetLights() {
		p := index("lights", i)
		if sun := l.GetSun(); sun != nil && toVec(sun.GetDirection()).isZero() {
			return rules.Errorf(p+".sun.direction", "must be non-zero")
		}
		spot := l.GetSpot()
		switch {
		case spot == nil:
		case toVec(spot.GetDirection()).isZero():
			return rules.Errorf(p+".spot.direction", "must be non-zero")
		case spot.GetInnerConeDegrees() > spot.GetOuterConeDegrees():
			return rules.Errorf(p+".spot.inner_cone_degrees", "must be at most outer_cone_degrees %s, got %s",
				rules.Number(spot.GetOuterConeDegrees()), rules.Number(spot.GetInnerConeDegrees()))
		}
	}
	return nil
}

func positive(c *pb.Color) bool { return c.GetR() > 0 || c.GetG() > 0 || c.GetB() > 0 }
