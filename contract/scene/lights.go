package scene

import (
	"fmt"

	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

// checkSomeLight: something emits (lights): a point or sun light with a positive
// component, or a shape whose material is emissive with a positive radiance.
func checkSomeLight(s *pb.Scene) *FieldError {
	for _, l := range s.GetLights() {
		var power *pb.Color
		switch k := l.GetKind().(type) {
		case *pb.Light_Point:
			power = k.Point.GetIntensity()
		case *pb.Light_Sun:
			power = k.Sun.GetIrradiance()
		default:
			panic(fmt.Sprintf("scene: checkSomeLight does not know light %T", k))
		}
		if positive(power) {
			return nil
		}
	}
	materials := materialsByName(s)
	for _, sh := range s.GetShapes() {
		if positive(materials[sh.GetMaterial()].GetEmissive().GetRadiance()) {
			return nil
		}
	}
	return rules.Errorf("lights", "the scene needs a light: a point or sun light with a positive component, "+
		"or a shape whose material is emissive with a positive radiance")
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

func positive(c *pb.Color) bool { return c.GetR() > 0 || c.GetG() > 0 || c.GetB() > 0 }
