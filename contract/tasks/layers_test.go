package tasks

import (
	"os"
	"regexp"
	"slices"
	"testing"
)

// The worker names the measured layers in C++; both sides must list the same ones in the
// same order, or a composite's layer errors are refused by the coordinator.
func TestMeasuredLayersMatchTheWorkers(t *testing.T) {
	const header = "../../worker/image/reference_exr.h"
	src, err := os.ReadFile(header)
	if err != nil {
		t.Fatal(err)
	}
	decl := regexp.MustCompile(`kMeasuredLayers = \{([^}]*)\}`).FindSubmatch(src)
	if decl == nil {
		t.Fatalf("%s: no kMeasuredLayers declaration", header)
	}
	var worker []string
	for _, m := range regexp.MustCompile(`"([a-z]+)"`).FindAllSubmatch(decl[1], -1) {
		worker = append(worker, string(m[1]))
	}
	if !slices.Equal(worker, MeasuredLayers) {
		t.Errorf("%s lists %q, contract/tasks %q", header, worker, MeasuredLayers)
	}
}
