package smoke

import (
	"bytes"
	"context"
	"io"
	"testing"

	"photonfarm/contract/assets"
	"photonfarm/contract/rules"
	"photonfarm/contract/scene"
)

// TestTheSceneAndItsPlumePassTheContract: the plume is a farm grid file every reader
// accepts, mostly empty (sparse smoke, where per-brick majorants pay) with a dense core,
// and the scene naming it validates once the client has set the file's digest.
func TestTheSceneAndItsPlumePassTheContract(t *testing.T) {
	var file bytes.Buffer
	g := Plume()
	if err := assets.EncodeFarmGrid(&file, g); err != nil {
		t.Fatal(err)
	}
	open := func() (io.ReadCloser, error) { return io.NopCloser(bytes.NewReader(file.Bytes())), nil }
	checked, err := assets.CheckFarmGrid(context.Background(), open, assets.SceneGridLimits())
	if err != nil {
		t.Fatal(err)
	}
	empty := 0
	for _, d := range g.Densities {
		if d == 0 {
			empty++
		}
	}
	if frac := float64(empty) / float64(len(g.Densities)); frac < 0.5 || checked.MaxDensity < 0.5 {
		t.Errorf("%.0f%% of the cells empty, largest density %g: want sparse smoke with a dense core", 100*frac, checked.MaxDensity)
	}
	s := Scene()
	files := scene.Files(s)
	if len(files) != 1 || files[0].Kind != scene.GridFile || files[0].Path != gridFile {
		t.Fatalf("files %+v, want the plume's grid", files)
	}
	files[0].SetDigest(rules.DigestOf(file.Bytes()))
	if err := scene.Validate(s); err != nil {
		t.Fatal(err)
	}
}
