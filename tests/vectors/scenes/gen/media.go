package main

import (
	"slices"

	pb "photonfarm/proto/renderfarm/v1"
)

// fog gives the scene a medium given by its coefficients and returns them.
func fog(s *pb.Scene) *pb.MediumCoefficients {
	c := &pb.MediumCoefficients{SigmaA: rgb(0.01, 0.01, 0.02), SigmaS: rgb(0.05, 0.05, 0.04)}
	s.Medium = &pb.Medium{Coefficients: &pb.Medium_Sigma{Sigma: c}, G: 0.3}
	return c
}

// murk gives the glass ball (shapes[5]) an interior medium given by albedo and density and
// returns them.
func murk(s *pb.Scene) *pb.MediumAlbedo {
	a := &pb.MediumAlbedo{Albedo: rgb(0.9, 0.7, 0.5), Density: 2}
	s.Shapes[5].InteriorMedium = &pb.Medium{Coefficients: &pb.Medium_Albedo{Albedo: a}, G: -0.2}
	return a
}

func fogG(s *pb.Scene, g float64) { fog(s); s.Medium.G = g }

func murkDensity(s *pb.Scene, d float64) { murk(s).Density = d }

// refusedMedia and acceptedMedia: media's coefficients missing, negative or past their
// bounds, g at and past +-1, and each inclusive bound exactly.
var refusedMedia = slices.Concat([]vectorCase{
	refuse("refuse-medium-without-coefficients", "medium", "Medium.coefficients:one_required", func(s *pb.Scene) {
		s.Medium = &pb.Medium{G: 0.5}
	}),
	refuse("refuse-medium-without-sigma-a", "medium.sigma.sigma_a", "MediumCoefficients.sigma_a:required", func(s *pb.Scene) { fog(s).SigmaA = nil }),
	refuse("refuse-medium-sigma-a-negative", "medium.sigma.sigma_a.g", "MediumCoefficients.sigma_a:gte", func(s *pb.Scene) { fog(s).SigmaA.G = -0.01 }),
	refuse("refuse-medium-without-sigma-s", "medium.sigma.sigma_s", "MediumCoefficients.sigma_s:required", func(s *pb.Scene) { fog(s).SigmaS = nil }),
	refuse("refuse-medium-sigma-s-negative", "medium.sigma.sigma_s.b", "MediumCoefficients.sigma_s:gte", func(s *pb.Scene) { fog(s).SigmaS.B = -1 }),
	refuse("refuse-medium-g-minus-1", "medium.g", "Medium.g:gt", func(s *pb.Scene) { fogG(s, -1) }),
	refuse("refuse-medium-g-1", "medium.g", "Medium.g:lt", func(s *pb.Scene) { fogG(s, 1) }),
	refuse("refuse-interior-medium-without-albedo", "shapes[5].interior_medium.albedo.albedo", "MediumAlbedo.albedo:required", func(s *pb.Scene) {
		murk(s).Albedo = nil
	}),
	refuse("refuse-interior-medium-albedo-negative", "shapes[5].interior_medium.albedo.albedo.r", "MediumAlbedo.albedo:gte", func(s *pb.Scene) {
		murk(s).Albedo.R = -0.5
	}),
	refuse("refuse-interior-medium-albedo-above-1", "shapes[5].interior_medium.albedo.albedo.b", "MediumAlbedo.albedo:lte", func(s *pb.Scene) {
		murk(s).Albedo.B = 1.5
	}),
	refuse("refuse-interior-medium-density-negative", "shapes[5].interior_medium.albedo.density", "MediumAlbedo.density:gte", func(s *pb.Scene) {
		murkDensity(s, -2)
	}),
}, nonFinite("refuse-medium-g", "medium.g", "Medium.g", fogG),
	nonFinite("refuse-interior-medium-density", "shapes[5].interior_medium.albedo.density", "MediumAlbedo.density", murkDensity))

var acceptedMedia = []vectorCase{
	accept("accept-medium-sigma-a-and-sigma-s-0", "MediumCoefficients.sigma_a:gte= MediumCoefficients.sigma_s:gte=", func(s *pb.Scene) {
		c := fog(s)
		c.SigmaA, c.SigmaS = rgb(0, 0.1, 0), rgb(0.2, 0, 0)
	}),
	accept("accept-interior-medium-albedo-0-and-1-density-0", "MediumAlbedo.albedo:gte= MediumAlbedo.albedo:lte= MediumAlbedo.density:gte=", func(s *pb.Scene) {
		a := murk(s)
		a.Albedo, a.Density = rgb(0, 1, 0.5), 0
	}),
	accept("accept-fog-and-murky-glass", "", func(s *pb.Scene) { fog(s); murk(s) }),
	accept("accept-fog-with-volume-photons-and-estimate", "", func(s *pb.Scene) {
		fog(s)
		s.Photons.VolumePhotons = 30000
		s.Photons.VolumeEstimate = &pb.RadianceEstimate{Neighbours: 80, MaxRadius: 0.25}
	}),
}
