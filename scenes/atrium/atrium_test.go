package atrium_test

import (
	"context"
	"path/filepath"
	"testing"

	"photonfarm/client/importer"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/scenes/atrium"
)

// TestAtriumIsWhatTheIssueAsksFor imports the generated atrium and checks it holds what
// issue 13's demonstration scene must: 250,000 triangles or more, 10 textures or more, an
// alpha-masked material, a sun, an environment map, and a mesh placed 100 times.
func TestAtriumIsWhatTheIssueAsksFor(t *testing.T) {
	dir := t.TempDir()
	st, err := atrium.Write(dir)
	if err != nil {
		t.Fatal(err)
	}
	if st.Triangles < 250000 {
		t.Errorf("%d triangles, want at least 250,000", st.Triangles)
	}
	r, err := importer.Import(context.Background(), filepath.Join(dir, "atrium.glb"), filepath.Join(dir, "scene"),
		importer.Options{Width: 64, Environment: filepath.Join(dir, "sky.hdr")})
	if err != nil {
		t.Fatal(err)
	}
	s := r.Scene
	if n := len(s.GetTextures()); n < 11 {
		t.Errorf("%d textures (with the sky), want at least 11", n)
	}
	uses := map[string]int{}
	for _, sh := range s.GetShapes() {
		uses[sh.GetInstance().GetMesh()]++
	}
	most := 0
	for _, n := range uses {
		most = max(most, n)
	}
	if most < 100 {
		t.Errorf("the most-used mesh is placed %d times, want 100", most)
	}
	masked := 0
	for _, m := range s.GetMaterials() {
		if m.GetPrincipled().GetAlphaMode() == pb.AlphaMode_ALPHA_MODE_MASK {
			masked++
		}
	}
	if masked < 2 {
		t.Errorf("%d alpha-masked materials, want the banners' and the leaves'", masked)
	}
	if len(s.GetLights()) != 1 || s.GetLights()[0].GetSun() == nil || s.GetEnvironment().GetMap() == nil {
		t.Errorf("lights %v, environment %v: want a sun and the sky map", s.GetLights(), s.GetEnvironment())
	}
}
