package main

import (
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

func grow(path string, count uint64) *pb.GrowField { return &pb.GrowField{Path: path, Count: count} }

// long is a string of n bytes.
func long(n int) string { return strings.Repeat("n", n) }

func unchanged(*pb.Scene) {}
