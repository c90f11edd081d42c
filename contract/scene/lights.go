package scene

import (
	"math"

	pb "photonfarm/proto/renderfarm/v1"
)

// validateLights checks the lights without geometry and returns how many emit (have a
// positive intensity or irradiance).
func validateLights(ls []*pb.Light) (int, error) {
	if len(ls) > MaxLights {
		return 0, fe("lights", "must have at most %d entries, got %d", MaxLights, len(ls))
	}
	emitting := 0
	for i, l := range ls {
		p := idx("lights", i)
		if err := checkName(p+".name", l.GetName()); err != nil {
			return 0, err
		}
		var power *pb.Color
		switch k := l.GetKind().(type) {
		case *pb.Light_Point:
			if _, err := requiredVec3(p+".point.position", k.Point.GetPosition()); err != nil {
				return 0, err
			}
			power = k.Point.GetIntensity()
			if err := checkColor(p+".point.intensity", power, math.Inf(1)); err != nil {
				return 0, err
			}
		case *pb.Light_Sun:
			dir, err := requiredVec3(p+".sun.direction", k.Sun.GetDirection())
			if err != nil {
				return 0, err
			}
			if dir.isZero() {
				return 0, fe(p+".sun.direction", "must be non-zero")
			}
			power = k.Sun.GetIrradiance()
			if err := checkColor(p+".sun.irradiance", power, math.Inf(1)); err != nil {
				return 0, err
			}
		default:
			return 0, fe(p, "exactly one kind (point, sun) must be set")
		}
		if power.GetR() > 0 || power.GetG() > 0 || power.GetB() > 0 {
			emitting++
		}
	}
	return emitting, nil
}
