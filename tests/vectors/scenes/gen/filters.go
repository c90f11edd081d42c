package main

import (
	"fmt"
	"slices"

	pb "photonfarm/proto/renderfarm/v1"
)

// filterRadius is one pixel filter's radius field, for the cases every filter shares.
type filterRadius struct {
	name    string // as in file names: box, tent, gaussian, mitchell
	message string // its message in scene.proto
	set     func(s *pb.Scene, radius float64)
}

var filterRadii = []filterRadius{
	{"box", "BoxFilter", func(s *pb.Scene, r float64) {
		s.Film.Filter = &pb.PixelFilter{Kind: &pb.PixelFilter_Box{Box: &pb.BoxFilter{Radius: r}}}
	}},
	{"tent", "TentFilter", func(s *pb.Scene, r float64) {
		s.Film.Filter = &pb.PixelFilter{Kind: &pb.PixelFilter_Tent{Tent: &pb.TentFilter{Radius: r}}}
	}},
	{"gaussian", "GaussianFilter", func(s *pb.Scene, r float64) {
		s.Film.Filter = &pb.PixelFilter{Kind: &pb.PixelFilter_Gaussian{Gaussian: &pb.GaussianFilter{Radius: r}}}
	}},
	{"mitchell", "MitchellFilter", func(s *pb.Scene, r float64) {
		s.Film.Filter = &pb.PixelFilter{Kind: &pb.PixelFilter_Mitchell{Mitchell: &pb.MitchellFilter{Radius: r}}}
	}},
}

func gaussianSigma(s *pb.Scene, sigma float64) {
	s.Film.Filter = &pb.PixelFilter{Kind: &pb.PixelFilter_Gaussian{Gaussian: &pb.GaussianFilter{Sigma: sigma}}}
}

// refusedFilters and acceptedFilters: each filter's radius (and the Gaussian's sigma) just
// outside and exactly at its bounds, 0 for its default, and not a finite number.
var refusedFilters, acceptedFilters = filterCases()

func filterCases() (refused, accepted []vectorCase) {
	for _, f := range filterRadii {
		field := "film.filter." + f.name + ".radius"
		key := f.message + ".radius"
		set := f.set
		refused = slices.Concat(refused, []vectorCase{
			refuse(fmt.Sprintf("refuse-%s-filter-radius-below-half-a-pixel", f.name), field, key+":gte", func(s *pb.Scene) { set(s, 0.25) }),
			refuse(fmt.Sprintf("refuse-%s-filter-radius-above-2", f.name), field, key+":lte", func(s *pb.Scene) { set(s, 2.5) }),
		}, nonFinite(fmt.Sprintf("refuse-%s-filter-radius", f.name), field, key, set))
		accepted = append(accepted,
			accept(fmt.Sprintf("accept-%s-filter-radius-half-a-pixel", f.name), key+":gte=", func(s *pb.Scene) { set(s, 0.5) }),
			accept(fmt.Sprintf("accept-%s-filter-radius-2", f.name), key+":lte=", func(s *pb.Scene) { set(s, 2) }),
			accept(fmt.Sprintf("accept-%s-filter-radius-0", f.name), key+":default", func(s *pb.Scene) { set(s, 0) }))
	}
	const sigma = "film.filter.gaussian.sigma"
	refused = slices.Concat(refused, []vectorCase{
		refuse("refuse-gaussian-filter-sigma-below-an-eighth", sigma, "GaussianFilter.sigma:gte", func(s *pb.Scene) { gaussianSigma(s, 0.1) }),
		refuse("refuse-gaussian-filter-sigma-above-2", sigma, "GaussianFilter.sigma:lte", func(s *pb.Scene) { gaussianSigma(s, 2.5) }),
	}, nonFinite("refuse-gaussian-filter-sigma", sigma, "GaussianFilter.sigma", gaussianSigma))
	accepted = append(accepted,
		accept("accept-gaussian-filter-sigma-an-eighth", "GaussianFilter.sigma:gte=", func(s *pb.Scene) { gaussianSigma(s, 0.125) }),
		accept("accept-gaussian-filter-sigma-2", "GaussianFilter.sigma:lte=", func(s *pb.Scene) { gaussianSigma(s, 2) }),
		accept("accept-gaussian-filter-sigma-0", "GaussianFilter.sigma:default", func(s *pb.Scene) { gaussianSigma(s, 0) }),
		accept("accept-film-without-a-filter", "", func(s *pb.Scene) { s.Film.Filter = nil }))
	return refused, accepted
}
