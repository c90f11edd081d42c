package dashboard_test

import (
	"encoding/json"
	"net/http"
	"os"
	"path/filepath"
	"strings"
	"testing"

	"photonfarm/contract/rules"
	"photonfarm/tests/farmtest"
)

// sceneNaming is sceneJSON's scene with two shapes that name the mesh file p.
func sceneNaming(t *testing.T, p string) map[string]any {
	t.Helper()
	var m map[string]any
	must(t, json.Unmarshal([]byte(sceneJSON(t, 16, 16)), &m))
	for _, name := range []string{"a", "b"} {
		m["shapes"] = append(m["shapes"].([]any), map[string]any{"name": name, "material": "white", "mesh": map[string]any{"path": p}})
	}
	return m
}

// TestSubmitSendsTheScenesFilesFromTheBrowser submits scenes with their mesh files in the
// body, as the front end does, against a real coordinator: each file is found by its path,
// its place in a chosen folder or its name alone, stored in the blob store, and the job
// queued; a missing, ambiguous or broken file is refused naming the field and the file,
// and nothing is queued.
func TestSubmitSendsTheScenesFilesFromTheBrowser(t *testing.T) {
	obj, err := os.ReadFile(filepath.Join(farmtest.RepoRoot(), "scenes", "meshes", "octahedron.obj"))
	must(t, err)
	broken := []byte("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n")
	cases := []struct {
		name  string
		path  string
		files map[string][]byte
		want  string // "" for a queued job, else what the 400 must say
	}{
		{"by its path", "meshes/octahedron.obj", map[string][]byte{"meshes/octahedron.obj": obj}, ""},
		{"within a chosen folder", "./meshes/octahedron.obj", map[string][]byte{"my-scene/meshes/octahedron.obj": obj, "my-scene/notes.txt": []byte("x")}, ""},
		{"by its name alone", "meshes/octahedron.obj", map[string][]byte{"octahedron.obj": obj}, ""},
		{"missing", "meshes/octahedron.obj", map[string][]byte{"cube.obj": obj},
			"names the file meshes/octahedron.obj, which was not sent with the scene (sent: cube.obj)"},
		{"ambiguous", "meshes/octahedron.obj", map[string][]byte{"a/octahedron.obj": obj, "b/octahedron.obj": obj},
			"several files sent with the scene could be it (a/octahedron.obj, b/octahedron.obj)"},
		{"broken", "meshes/octahedron.obj", map[string][]byte{"octahedron.obj": broken}, "mesh: meshes/octahedron.obj: line 4"},
	}
	for _, c := range cases {
		t.Run(c.name, func(t *testing.T) {
			f := newFarm(t)
			b := f.browser(clientToken)
			body, err := json.Marshal(map[string]any{"scene": sceneNaming(t, c.path), "files": c.files})
			must(t, err)
			r := f.do(b, "POST", "/api/jobs", string(body))
			jobs, err := f.c.ListJobs(f.ctx)
			must(t, err)
			if c.want != "" {
				wantStatus(t, c.name, r, http.StatusBadRequest)
				if !strings.Contains(r.Body, c.want) {
					t.Errorf("answer %s, want it to say %q", r.Body, c.want)
				}
				if len(jobs) != 0 {
					t.Errorf("%d jobs queued after a refusal", len(jobs))
				}
				return
			}
			wantStatus(t, c.name, r, http.StatusOK)
			if len(jobs) != 1 {
				t.Fatalf("%d jobs, want the one submitted", len(jobs))
			}
			if ok, err := f.c.BlobExists(f.ctx, rules.DigestOf(obj)); err != nil || !ok {
				t.Errorf("the mesh is not in the blob store: %v, %v", ok, err)
			}
		})
	}
}
