package planner

import (
	"testing"

	pb "photonfarm/proto/renderfarm/v1"
)

// A scene lit by its environment alone (as an imported model without lights is) names
// only the environment. Passes' own test covers the rest on valid scenes; this case is
// tested here because the scene rules of this branch do not count an environment as a
// light yet.
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
