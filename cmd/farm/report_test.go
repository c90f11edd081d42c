package main

import (
	"bytes"
	"encoding/xml"
	"io"
	"strconv"
	"strings"
	"testing"

	"google.golang.org/protobuf/proto"

	pb "photonfarm/proto/renderfarm/v1"
)

func rounds(n int, withEstimate, withReference bool) []*pb.RoundReport {
	var rs []*pb.RoundReport
	for i := 1; i <= n; i++ {
		r := &pb.RoundReport{Round: uint32(i), ElapsedSeconds: 2.5 * float64(i), Photons: uint64(400000 * i), SamplesPerPixel: uint64(i)}
		if withEstimate {
			r.ErrorEstimate = proto.Float64(0.08 / float64(i))
		}
		if withReference {
			r.ReferenceRmse = proto.Float64(0.05 / float64(i*i))
		}
		rs = append(rs, r)
	}
	return rs
}

// svgPoints parses the SVG as XML (failing on malformed documents) and returns, per series
// name, the rounds of its markers.
func svgPoints(t *testing.T, svg []byte) map[string][]string {
	t.Helper()
	dec := xml.NewDecoder(bytes.NewReader(svg))
	points := map[string][]string{}
	series, root := "", ""
	for {
		tok, err := dec.Token()
		if err == io.EOF {
			break
		}
		if err != nil {
			t.Fatalf("SVG is not well-formed XML: %v\n%s", err, svg)
		}
		el, ok := tok.(xml.StartElement)
		if !ok {
			continue
		}
		if root == "" {
			root = el.Name.Local
		}
		attr := map[string]string{}
		for _, a := range el.Attr {
			attr[a.Name.Local] = a.Value
		}
		switch {
		case el.Name.Local == "g" && attr["class"] == "series":
			series = attr["data-name"]
		case attr["class"] == "point":
			points[series] = append(points[series], attr["data-round"])
		}
	}
	if root != "svg" {
		t.Fatalf("root element %q, want svg", root)
	}
	return points
}

func TestPlotIsWellFormedWithOnePointPerRound(t *testing.T) {
	tests := []struct {
		name       string
		rounds     []*pb.RoundReport
		wantSeries map[string]int
	}{
		{"estimate and reference", rounds(5, true, true), map[string]int{
			"estimated error": 5, "RMSE against the reference": 5}},
		{"estimate only", rounds(4, true, false), map[string]int{"estimated error": 4}},
		{"one round", rounds(1, false, true), map[string]int{"RMSE against the reference": 1}},
		{"no error yet", rounds(1, false, false), map[string]int{}},
		{"title to escape", rounds(2, true, false), map[string]int{"estimated error": 2}},
	}
	for _, tt := range tests {
		t.Run(tt.name, func(t *testing.T) {
			var b bytes.Buffer
			if err := writePlot(&b, `cornell <&> "box"`, tt.rounds); err != nil {
				t.Fatal(err)
			}
			got := svgPoints(t, b.Bytes())
			if len(got) != len(tt.wantSeries) {
				t.Errorf("series %v, want %v", got, tt.wantSeries)
			}
			for name, n := range tt.wantSeries {
				if len(got[name]) != n {
					t.Errorf("series %q has points for rounds %v, want %d", name, got[name], n)
				}
				for i, r := range got[name] {
					if want := tt.rounds[i].GetRound(); r != itoa(want) {
						t.Errorf("point %d is round %s, want %d", i, r, want)
					}
				}
			}
			for _, label := range []string{"elapsed time", "RMSE of the image", "log scale"} {
				if len(tt.wantSeries) > 0 && !strings.Contains(b.String(), label) {
					t.Errorf("plot lacks the axis label %q", label)
				}
			}
		})
	}
}

func itoa(n uint32) string { return strconv.FormatUint(uint64(n), 10) }

func TestReportTable(t *testing.T) {
	job := &pb.Job{Id: "j-1", DisplayName: "cornell", State: pb.JobState_JOB_STATE_SUCCEEDED, Rounds: rounds(3, false, false)}
	job.Rounds[1].ErrorEstimate = proto.Float64(0.0125)
	job.Rounds[1].ErrorEstimateBias = proto.Float64(0.002)
	job.Rounds[1].ErrorEstimateLow = proto.Float64(0.0101)
	job.Rounds[1].ErrorEstimateHigh = proto.Float64(0.0163)
	var b strings.Builder
	printReport(&b, job)
	lines := strings.Split(strings.TrimSpace(b.String()), "\n")
	if len(lines) != 5 {
		t.Fatalf("report = %q, want a title, a header and 3 rounds", b.String())
	}
	if !strings.Contains(lines[0], "succeeded, 3 rounds") {
		t.Errorf("title = %q", lines[0])
	}
	for _, column := range []string{"estimated error", "95% interval", "of it bias", "reference RMSE"} {
		if !strings.Contains(lines[1], column) {
			t.Errorf("header %q lacks %q", lines[1], column)
		}
	}
	if f := strings.Fields(lines[3]); len(f) != 8 || f[0] != "2" || f[1] != "5.00" || f[2] != "800,000" || f[4] != "0.0125" ||
		f[5] != "0.0101-0.0163" || f[6] != "0.002" || f[7] != "-" {
		t.Errorf("round 2 = %q", lines[3])
	}
	if f := strings.Fields(lines[2]); len(f) != 8 || f[4] != "-" || f[5] != "-" || f[6] != "-" {
		t.Errorf("round 1 = %q, want no estimate", lines[2])
	}
}

func TestReportSaysWhereTheSamplesWent(t *testing.T) {
	job := &pb.Job{Id: "j-1", State: pb.JobState_JOB_STATE_SUCCEEDED, Rounds: rounds(3, false, false)}
	job.Rounds[0].Samples = &pb.SampleSpread{Layer: "samples.Y", Min: 1, Mean: 1.5, Max: 12}
	job.Rounds[2].Samples = &pb.SampleSpread{Layer: "samples.Y", Min: 3, Mean: 4.5, Max: 40, TopErrorDecileShare: proto.Float64(0.254)}
	var b strings.Builder
	printReport(&b, job)
	lines := strings.Split(strings.TrimSpace(b.String()), "\n")
	want := "samples after round 3 (layer samples.Y of the EXR): 3 to 40 a pixel, mean 4.50; the 10% of pixels with the largest estimated error drew 25.4% of them"
	if last := lines[len(lines)-1]; last != want {
		t.Errorf("last line = %q, want %q", last, want)
	}
}

func TestReportTableHasAColumnPerMeasuredLayer(t *testing.T) {
	job := &pb.Job{Id: "j-1", State: pb.JobState_JOB_STATE_SUCCEEDED, Rounds: rounds(2, false, true)}
	job.Rounds[1].LayerReferenceRmse = map[string]float64{"indirect": 0.002, "direct": 0.0005}
	var b strings.Builder
	printReport(&b, job)
	lines := strings.Split(strings.TrimSpace(b.String()), "\n")
	if len(lines) != 4 || !strings.HasSuffix(strings.TrimSpace(lines[1]), "reference RMSE  direct RMSE  indirect RMSE") {
		t.Fatalf("report = %q, want direct and indirect columns, in that order", b.String())
	}
	if f := strings.Fields(lines[2]); len(f) != 10 || f[8] != "-" || f[9] != "-" {
		t.Errorf("round 1 = %q, want no layer errors", lines[2])
	}
	if f := strings.Fields(lines[3]); len(f) != 10 || f[8] != "0.0005" || f[9] != "0.002" {
		t.Errorf("round 2 = %q", lines[3])
	}
}

func TestPrintPlan(t *testing.T) {
	plan := &pb.Plan{Passes: []*pb.PlannedPass{
		{Name: "global photon map", Enabled: true, Reason: "200,000 paths"},
		{Name: "caustic photon map", Reason: "no specular surface (mirror, glass, metal)"},
	}}
	var b strings.Builder
	printPlan(&b, plan, []*pb.PhaseProgress{{Phase: pb.Phase_PHASE_EMIT, TasksTotal: 2}, {Phase: pb.Phase_PHASE_RENDER, TasksTotal: 4}})
	want := "  run   global photon map   200,000 paths\n" +
		"  skip  caustic photon map  no specular surface (mirror, glass, metal)\n" +
		"tasks per phase (round 1): emit 2, render 4\n"
	if b.String() != want {
		t.Errorf("plan =\n%s\nwant\n%s", b.String(), want)
	}
}
