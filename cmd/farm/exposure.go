package main

import (
	"fmt"
	"math"
	"strconv"

	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

// exposureFlag adds --exposure to fs: stops that override the scene's
// output.exposure_stops (the PNG preview is scaled by 2^stops before its tone map; the EXR
// stays linear). The value is nil while the flag is not given; a value outside the bounds
// scene.proto declares is refused as the flag is parsed.
func exposureFlag(fs *flagSet) **float64 {
	var stops *float64
	lo, hi := rules.Min((*pb.Output)(nil), "exposure_stops"), rules.Max((*pb.Output)(nil), "exposure_stops")
	fs.Func("exposure", fmt.Sprintf("exposure of the PNG preview in `stops` (+1 twice as bright), from %s to %s; overrides the scene's output.exposure_stops",
		rules.Number(lo), rules.Number(hi)), func(text string) error {
		v, err := strconv.ParseFloat(text, 64)
		if err != nil || math.IsNaN(v) || v < lo || v > hi {
			return fmt.Errorf("must be a number of stops from %s to %s", rules.Number(lo), rules.Number(hi))
		}
		stops = &v
		return nil
	})
	return &stops
}

// setExposure sets s's output.exposure_stops, keeping the rest of its output settings.
func setExposure(s *pb.Scene, stops float64) {
	if s.Output == nil {
		s.Output = &pb.Output{}
	}
	s.Output.ExposureStops = stops
}
