package main

import (
	"slices"

	"photonfarm/contract/assets/assetstest"
	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

// rampGrid is the farm grid file of the cases that need one (assetstest.RampGrid); the
// generator writes it to tests/vectors/scenes/ramp.farmgrid.
var rampGrid = string(assetstest.EncodedGrid(assetstest.RampGrid()))

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

// smoke gives the scene a grid medium (the ramp grid, uploaded) and returns it.
func smoke(s *pb.Scene) *pb.MediumGrid {
	g := &pb.MediumGrid{Path: "ramp.farmgrid", Digest: rules.DigestOf([]byte(rampGrid)), Albedo: rgb(0.9, 0.9, 0.8), DensityScale: 0.5}
	s.Medium = &pb.Medium{Coefficients: &pb.Medium_Grid{Grid: g}, G: 0.4}
	return g
}

// smokyGlass gives the glass ball (shapes[5]) the ramp grid as its interior medium, placed
// inside the ball, and returns it.
func smokyGlass(s *pb.Scene) *pb.MediumGrid {
	g := &pb.MediumGrid{Path: "ramp.farmgrid", Digest: rules.DigestOf([]byte(rampGrid)), Albedo: rgb(0.5, 0.6, 0.7),
		Transform: &pb.Transform{Translation: v(-1, 0.4, 2), Scale: v(0.2, 0.2, 0.2)}}
	s.Shapes[5].InteriorMedium = &pb.Medium{Coefficients: &pb.Medium_Grid{Grid: g}}
	return g
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
	refuse("refuse-medium-grid-path-of-4097-bytes", "medium.grid.path", "MediumGrid.path:max_bytes", func(s *pb.Scene) { smoke(s).Path = long(4097) }),
	refuse("refuse-medium-grid-without-digest", "medium.grid.digest", "MediumGrid.digest:required", func(s *pb.Scene) { smoke(s).Digest = "" }),
	refuse("refuse-medium-grid-digest-malformed", "medium.grid.digest", "MediumGrid.digest:digest", func(s *pb.Scene) { smoke(s).Digest = badDigest }),
	refuse("refuse-medium-grid-of-no-uploaded-file", "medium.grid.digest", "MediumGrid.digest:note", func(s *pb.Scene) { smoke(s).Digest = absentDigest }),
	refuse("refuse-interior-medium-grid-of-no-uploaded-file", "shapes[5].interior_medium.grid.digest", "MediumGrid.digest:note", func(s *pb.Scene) {
		smokyGlass(s).Digest = absentDigest
	}),
	refuse("refuse-medium-grid-without-albedo", "medium.grid.albedo", "MediumGrid.albedo:required", func(s *pb.Scene) { smoke(s).Albedo = nil }),
	refuse("refuse-medium-grid-albedo-negative", "medium.grid.albedo.g", "MediumGrid.albedo:gte", func(s *pb.Scene) { smoke(s).Albedo.G = -0.1 }),
	refuse("refuse-interior-medium-grid-albedo-above-1", "shapes[5].interior_medium.grid.albedo.r", "MediumGrid.albedo:lte", func(s *pb.Scene) {
		smokyGlass(s).Albedo.R = 1.01
	}),
	refuse("refuse-medium-grid-density-scale-negative", "medium.grid.density_scale", "MediumGrid.density_scale:gt", func(s *pb.Scene) { smoke(s).DensityScale = -1 }),
	refuse("refuse-medium-grid-scale-x-0", "medium.grid.transform.scale.x", "Transform.scale:note", func(s *pb.Scene) {
		smoke(s).Transform = &pb.Transform{Scale: v(0, 1, 1)}
	}),
}, nonFinite("refuse-medium-g", "medium.g", "Medium.g", fogG),
	nonFinite("refuse-medium-grid-density-scale", "medium.grid.density_scale", "MediumGrid.density_scale", func(s *pb.Scene, x float64) { smoke(s).DensityScale = x }),
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
	accept("accept-smoke-grid-filling-the-scene", "", func(s *pb.Scene) { smoke(s) }),
	accept("accept-smoke-grid-in-glass-density-scale-unset", "MediumGrid.density_scale:default", func(s *pb.Scene) { smokyGlass(s) }),
	accept("accept-medium-grid-albedo-0-and-1-path-of-4096-bytes", "MediumGrid.albedo:gte= MediumGrid.albedo:lte= MediumGrid.path:max_bytes=", func(s *pb.Scene) {
		g := smoke(s)
		g.Albedo, g.Path = rgb(0, 1, 1), long(4096)
	}),
	accept("accept-medium-grid-placed-by-a-matrix", "", func(s *pb.Scene) {
		smoke(s).Transform = &pb.Transform{Matrix: []float64{0, 0, 2, 1, 0, 2, 0, 0, -2, 0, 0, 0}}
	}),
	accept("accept-fog-with-volume-photons-and-estimate", "", func(s *pb.Scene) {
		fog(s)
		s.Photons.VolumePhotons = 30000
		s.Photons.VolumeEstimate = &pb.RadianceEstimate{Neighbours: 80, MaxRadius: 0.25}
	}),
}
