package planner

import (
	"testing"

	pb "photonfarm/proto/renderfarm/v1"
)

// A scene lit by its environment alone (as an imported model without lights is) names
// only the environment. Passes' own test covers the other cases on valid scenes; this one
// is checked on a bare scene, since lightTargets reads only the lights, the emissive
// shapes and the environment.
func TestLightTargetsOfAnEnvironmentAlone(t *testing.T) {
	s := &pb.Scene{Environment: &pb.Environment{Radiance: &pb.Color{R: 1, G: 1, B: 1}}}
	if got, want := lightTargets(s), "the environment"; got != want {
		t.Errorf("lightTargets = %q, want %q", got, want)
	}
	s.Environment.Radiance = &pb.Color{}
	if got, want := lightTargets(s), "0 lights; the environment is black: no shadow rays to it and no photons from it"; got != want {
		t.Errorf("lightTargets of a black environment = %q, want %q", got, want)
	}
}
