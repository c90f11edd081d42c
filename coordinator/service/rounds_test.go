package service_test

import (
	"strings"
	"testing"

	"google.golang.org/protobuf/proto"

	"photonfarm/coordinator/service"
	pb "photonfarm/proto/renderfarm/v1"
)

func TestStopReason(t *testing.T) {
	const ref = "sha256:0123456789abcdef0123456789abcdef0123456789abcdef0123456789abcdef"
	prog := func(max uint32, target, budget float64, reference bool) *pb.Scene {
		p := &pb.Progressive{MaxRounds: max, TargetError: target, TimeBudgetSeconds: budget}
		if reference {
			p.Reference = &pb.ReferenceImage{Digest: ref}
		}
		return &pb.Scene{Progressive: p}
	}
	round := func(r uint32, elapsed float64, est, rmse *float64) *pb.RoundReport {
		return &pb.RoundReport{Round: r, ElapsedSeconds: elapsed, ErrorEstimate: est, ReferenceRmse: rmse}
	}
	f := proto.Float64
	tests := []struct {
		name  string
		scene *pb.Scene
		round *pb.RoundReport
		want  string // substring; "" means go on
	}{
		{"single round", &pb.Scene{}, round(1, 1, nil, nil), "max rounds (1)"},
		{"more rounds to go", prog(4, 0, 0, false), round(2, 1, f(0.1), nil), ""},
		{"max rounds", prog(4, 0, 0, false), round(4, 1, f(0.1), nil), "max rounds (4)"},
		{"estimate meets target", prog(10, 0.05, 0, false), round(3, 1, f(0.05), nil), "error estimate"},
		{"estimate above target", prog(10, 0.05, 0, false), round(3, 1, f(0.051), nil), ""},
		{"no estimate in round 1", prog(10, 0.05, 0, false), round(1, 1, nil, nil), ""},
		{"reference decides when given", prog(10, 0.05, 0, true), round(3, 1, f(0.01), f(0.2)), ""},
		{"reference meets target", prog(10, 0.05, 0, true), round(3, 1, f(0.2), f(0.04)), "reference RMSE"},
		{"budget spent", prog(10, 0, 30, false), round(3, 30.5, nil, nil), "time budget"},
		{"budget left", prog(10, 0, 30, false), round(3, 29, nil, nil), ""},
	}
	for _, tt := range tests {
		t.Run(tt.name, func(t *testing.T) {
			got := service.StopReason(tt.scene, tt.round)
			if (tt.want == "") != (got == "") || !strings.Contains(got, tt.want) {
				t.Errorf("StopReason = %q, want %q", got, tt.want)
			}
		})
	}
}
