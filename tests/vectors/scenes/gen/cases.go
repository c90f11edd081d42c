package main

import (
	"math"
	"strings"

	pb "photonfarm/proto/renderfarm/v1"
)

// vectorCase is one generated vector: base with one change. refused is the field every
// side's refusal must name, "" for a scene every side must accept; covers lists the keys
// (keys.go) it exercises.
type vectorCase struct {
	name    string
	refused string
	covers  []string
	mutate  func(*pb.Scene)
	grow    []*pb.GrowField
}

// refuse and accept make the cases of the tables in refused.go and accepted.go; covers is
// a space-separated list of keys.
func refuse(name, field, covers string, mutate func(*pb.Scene), grow ...*pb.GrowField) vectorCase {
	return vectorCase{name: name, refused: field, covers: strings.Fields(covers), mutate: mutate, grow: grow}
}

func accept(name, covers string, mutate func(*pb.Scene), grow ...*pb.GrowField) vectorCase {
	return vectorCase{name: name, covers: strings.Fields(covers), mutate: mutate, grow: grow}
}

// nonFinite returns the refusals of a double field (field, set by set) that is NaN,
// infinite or past max_magnitude, named prefix-nan, prefix-infinite and
// prefix-past-max-magnitude, covering key's nan, inf and magnitude checks.
func nonFinite(prefix, field, key string, set func(*pb.Scene, float64)) []vectorCase {
	var cases []vectorCase
	for _, c := range []struct {
		suffix, check string
		value         float64
	}{{"nan", "nan", math.NaN()}, {"infinite", "inf", math.Inf(1)}, {"past-max-magnitude", "magnitude", -2e12}} {
		cases = append(cases, refuse(prefix+"-"+c.suffix, field, key+":"+c.check, func(s *pb.Scene) { set(s, c.value) }))
	}
	return cases
}

func grow(path string, count uint64) *pb.GrowField { return &pb.GrowField{Path: path, Count: count} }

// long is a string of n bytes.
func long(n int) string { return strings.Repeat("n", n) }

func unchanged(*pb.Scene) {}
