package main

import (
	"slices"

	pb "photonfarm/proto/renderfarm/v1"
)

// abbe and glass give the glass (materials[4]) a dispersion.
func abbe(s *pb.Scene, v float64) {
	dielectric(s).Dispersion = &pb.Dispersion{Law: &pb.Dispersion_AbbeNumber{AbbeNumber: v}}
}

func glass(s *pb.Scene, g pb.Glass) {
	dielectric(s).Dispersion = &pb.Dispersion{Law: &pb.Dispersion_Glass{Glass: g}}
}

// refusedDispersion and acceptedDispersion: a dispersion without a law, Abbe numbers
// past their bounds and at each, an unknown glass, the default glass (BK7).
var refusedDispersion = slices.Concat([]vectorCase{
	refuse("refuse-dispersion-without-law", "materials[4].dielectric.dispersion", "Dispersion.law:one_required", func(s *pb.Scene) {
		dielectric(s).Dispersion = &pb.Dispersion{}
	}),
	refuse("refuse-abbe-number-below-15", "materials[4].dielectric.dispersion.abbe_number", "Dispersion.abbe_number:gte", func(s *pb.Scene) { abbe(s, 14.9) }),
	refuse("refuse-abbe-number-0", "materials[4].dielectric.dispersion.abbe_number", "Dispersion.abbe_number:gte", func(s *pb.Scene) { abbe(s, 0) }),
	refuse("refuse-abbe-number-above-100", "materials[4].dielectric.dispersion.abbe_number", "Dispersion.abbe_number:lte", func(s *pb.Scene) { abbe(s, 100.5) }),
	refuse("refuse-unknown-glass", "materials[4].dielectric.dispersion.glass", "Dispersion.glass:enum", func(s *pb.Scene) { glass(s, 9) }),
}, nonFinite("refuse-abbe-number", "materials[4].dielectric.dispersion.abbe_number", "Dispersion.abbe_number", abbe))

var acceptedDispersion = []vectorCase{
	accept("accept-abbe-number-15", "Dispersion.abbe_number:gte=", func(s *pb.Scene) { abbe(s, 15) }),
	accept("accept-abbe-number-100", "Dispersion.abbe_number:lte=", func(s *pb.Scene) { abbe(s, 100) }),
	accept("accept-glass-unspecified-is-bk7", "", func(s *pb.Scene) { glass(s, pb.Glass_GLASS_UNSPECIFIED) }),
	accept("accept-glass-sf11", "", func(s *pb.Scene) { glass(s, pb.Glass_GLASS_SF11) }),
}
