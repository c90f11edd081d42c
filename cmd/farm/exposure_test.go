package main

import (
	"strings"
	"testing"

	pb "photonfarm/proto/renderfarm/v1"
)

func TestExposureFlagOverridesTheScenesStops(t *testing.T) {
	for _, c := range []struct {
		args  []string
		given bool
		want  float64
	}{
		{nil, false, 0},
		{[]string{"--exposure", "+1"}, true, 1},
		{[]string{"--exposure=-2.5"}, true, -2.5},
		{[]string{"--exposure", "20"}, true, 20},
		{[]string{"--exposure", "0"}, true, 0},
	} {
		fs := newFlags("render", &env{stdout: &strings.Builder{}})
		exposure := exposureFlag(fs)
		if _, err := parse(fs, append([]string{"scene.json"}, c.args...), 1, 1); err != nil {
			t.Fatalf("%q: %v", c.args, err)
		}
		if (*exposure != nil) != c.given {
			t.Fatalf("%q: given = %v, want %v", c.args, *exposure != nil, c.given)
		}
		if !c.given {
			continue
		}
		s := &pb.Scene{Output: &pb.Output{ToneMap: pb.ToneMap_TONE_MAP_CLAMP, ExposureStops: 3}}
		setExposure(s, **exposure)
		if s.GetOutput().GetExposureStops() != c.want || s.GetOutput().GetToneMap() != pb.ToneMap_TONE_MAP_CLAMP {
			t.Errorf("%q: output = %v, want %v stops and the tone map kept", c.args, s.GetOutput(), c.want)
		}
		bare := &pb.Scene{}
		setExposure(bare, **exposure)
		if bare.GetOutput().GetExposureStops() != c.want {
			t.Errorf("%q on a scene without output: %v", c.args, bare.GetOutput())
		}
	}
}

func TestExposureFlagRefusesWhatScenesRefuse(t *testing.T) {
	for _, v := range []string{"20.5", "-21", "NaN", "+Inf", "bright", ""} {
		fs := newFlags("render", &env{stdout: &strings.Builder{}})
		exposureFlag(fs)
		_, err := parse(fs, []string{"scene.json", "--exposure", v}, 1, 1)
		if err == nil || !strings.Contains(err.Error(), "must be a number of stops from -20 to 20") {
			t.Errorf("--exposure %q: %v", v, err)
		}
	}
}
