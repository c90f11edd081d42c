package integration

import (
	"encoding/json"
	"os"
	"path/filepath"
	"strconv"
	"strings"
	"testing"
	"time"

	"photonfarm/client/importer/importertest"
	"photonfarm/contract/assets"
	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

// model is a model file the farm imports, made by the test, and how its film comes out at
// a width of modelWidth.
type model struct {
	name   string
	write  func(t *testing.T) string // writes the model and returns its path
	height int
}

const modelWidth = 48

// models are importertest's glTF (a quad mesh placed twice, alpha-masked with a checker
// texture, a camera of aspect ratio 2 and a point light) as a binary, as a .gltf with its
// buffer in a file beside it and as one with the buffer embedded as a data: URI, and its
// OBJ of two materials with their MTL file and texture (4:3, lit by a white sky).
var models = []model{
	{name: "model.glb", height: modelWidth / 2, write: func(t *testing.T) string {
		return importertest.Save(t, importertest.Model(t), "model.glb")
	}},
	{name: "external.gltf", height: modelWidth / 2, write: func(t *testing.T) string {
		doc := importertest.Model(t)
		importertest.ExternalBuffers(doc, "external")
		path := importertest.Save(t, doc, "external.gltf")
		checkGLTFBuffer(t, path, false)
		return path
	}},
	{name: "embedded.gltf", height: modelWidth / 2, write: func(t *testing.T) string {
		path := importertest.Save(t, importertest.Model(t), "embedded.gltf")
		checkGLTFBuffer(t, path, true)
		return path
	}},
	{name: "quads.obj", height: modelWidth * 3 / 4, write: func(t *testing.T) string {
		return importertest.WriteOBJ(t, true)
	}},
}

// checkGLTFBuffer checks that the .gltf at path holds its one buffer as a data: URI
// (embedded) or names a file beside it that exists.
func checkGLTFBuffer(t *testing.T, path string, embedded bool) {
	t.Helper()
	var doc struct {
		Buffers []struct{ URI string } `json:"buffers"`
	}
	b, err := os.ReadFile(path)
	if err == nil {
		err = json.Unmarshal(b, &doc)
	}
	if err != nil || len(doc.Buffers) != 1 {
		t.Fatalf("%s: %v, buffers %v; want one buffer", path, err, doc.Buffers)
	}
	uri := doc.Buffers[0].URI
	if strings.HasPrefix(uri, "data:") != embedded {
		t.Fatalf("%s: buffer URI %.40q, want embedded %v", path, uri, embedded)
	}
	if !embedded {
		if _, err := os.Stat(filepath.Join(filepath.Dir(path), uri)); err != nil {
			t.Fatalf("%s: its buffer file: %v", path, err)
		}
	}
}

// TestFarmRenderOfGLTFAndOBJModelsWritesEXRAndPNG: `farm render MODEL` imports each model
// directly, renders it on a two-worker farm of its own and writes OUT/STEM.exr (tiled
// FLOAT RGBA at the film the import chose) and OUT/STEM.png of the same size with lit
// pixels.
func TestFarmRenderOfGLTFAndOBJModelsWritesEXRAndPNG(t *testing.T) {
	tile := int(rules.Default(&pb.Film{}, "tile_size"))
	for _, m := range models {
		t.Run(m.name, func(t *testing.T) {
			src := m.write(t)
			out := filepath.Join(t.TempDir(), "out")
			cmd, stdout, stderr, tmp := farmRender(t, src, "-o", out, "--workers", "2", "--width", "48")
			if code := waitTimeout(t, cmd, 120*time.Second); code != 0 {
				t.Fatalf("farm render %s: exit status %d\nstdout: %s\nstderr: %s", m.name, code, stdout, stderr)
			}
			stem := strings.TrimSuffix(m.name, filepath.Ext(m.name))
			exr, err := os.ReadFile(filepath.Join(out, stem+".exr"))
			if err != nil {
				t.Fatal(err)
			}
			if err := checkFinalEXR(exr, modelWidth, m.height, tile); err != nil {
				t.Error(err)
			}
			png, err := os.ReadFile(filepath.Join(out, stem+".png"))
			if err != nil {
				t.Fatal(err)
			}
			if w, h, err := pngSize(png); err != nil || w != modelWidth || h != m.height {
				t.Errorf("%s.png: %dx%d, %v; want %dx%d", stem, w, h, err, modelWidth, m.height)
			}
			lit, _, err := pngLitAndCovered(png)
			t.Logf("%s.png: %d of %d pixels lit", stem, lit, modelWidth*m.height)
			if err != nil || lit == 0 {
				t.Errorf("%s.png: %d lit pixels (%v), want the model seen", stem, lit, err)
			}
			if left := leftovers(t, tmp); len(left) != 0 {
				t.Errorf("farm render left %v in its temporary folder (the import's folder among them?)", left)
			}
		})
	}
}

// TestFarmImportWritesASceneThatNamesItsMeshesAndImagesByPath: `farm import MODEL -o
// DIR/scene.json` writes a scene whose meshes (farm mesh files) and images (the model's
// own bytes) are files beside it named by relative paths, with no array of numbers longer
// than a transform's 12 anywhere in the JSON; and the scene renders with `farm render`,
// which uploads those files as blobs.
func TestFarmImportWritesASceneThatNamesItsMeshesAndImagesByPath(t *testing.T) {
	for _, m := range []model{models[0], models[3]} {
		t.Run(m.name, func(t *testing.T) {
			dir := t.TempDir()
			scenePath := filepath.Join(dir, "scene.json")
			code, stdout, stderr := farmtest.RunFarm(t, 60*time.Second, nil, "import", m.write(t), "-o", scenePath, "--width", "32")
			if code != 0 {
				t.Fatalf("farm import: exit status %d\nstdout: %s\nstderr: %s", code, stdout, stderr)
			}
			text, err := os.ReadFile(scenePath)
			if err != nil {
				t.Fatal(err)
			}
			var tree any
			if err := json.Unmarshal(text, &tree); err != nil {
				t.Fatal(err)
			}
			if path, n := longestNumberArray(tree, ""); n > 12 {
				t.Errorf("%s is an array of %d numbers: data inlined in the scene", path, n)
			}
			var sc struct {
				Meshes []struct {
					Parts []struct{ Path, Digest string }
				}
				Textures []struct{ Path, Digest string }
			}
			json.Unmarshal(text, &sc)
			if len(sc.Meshes) != 1 || len(sc.Textures) != 1 {
				t.Fatalf("scene has %d meshes and %d textures, want the model's one of each", len(sc.Meshes), len(sc.Textures))
			}
			for _, p := range sc.Meshes[0].Parts {
				data, err := os.ReadFile(filepath.Join(dir, p.Path))
				if err != nil || filepath.IsAbs(p.Path) || p.Digest != "" || !assets.IsFarmMesh(data) {
					t.Errorf("mesh part path %q digest %q: %v; want a farm mesh file beside the scene, named relatively, no digest", p.Path, p.Digest, err)
				}
			}
			image, err := os.ReadFile(filepath.Join(dir, sc.Textures[0].Path))
			if side := map[bool]int{true: 2, false: 4}[strings.HasSuffix(m.name, ".obj")]; err != nil ||
				string(image) != string(importertest.Checker(t, side)) {
				t.Errorf("texture %q: %v; want the model's image as it came", sc.Textures[0].Path, err)
			}

			out := filepath.Join(t.TempDir(), "out")
			cmd, rstdout, rstderr, _ := farmRender(t, scenePath, "-o", out, "--workers", "1")
			if code := waitTimeout(t, cmd, 120*time.Second); code != 0 {
				t.Fatalf("farm render of the imported scene: exit status %d\nstdout: %s\nstderr: %s", code, rstdout, rstderr)
			}
			// Named after the scene's name, which the import took from the model's file
			// (as farm fetch would name the job's files), not after scene.json.
			if _, err := os.Stat(filepath.Join(out, strings.TrimSuffix(m.name, filepath.Ext(m.name))+".exr")); err != nil {
				t.Error(err)
			}
		})
	}
}

// longestNumberArray returns the path and length of the longest array of numbers in a
// JSON tree.
func longestNumberArray(v any, path string) (string, int) {
	best, n := "", 0
	consider := func(p string, m int) {
		if m > n {
			best, n = p, m
		}
	}
	switch x := v.(type) {
	case map[string]any:
		for k, e := range x {
			consider(longestNumberArray(e, path+"."+k))
		}
	case []any:
		numbers := true
		for i, e := range x {
			_, isNumber := e.(float64)
			numbers = numbers && isNumber
			consider(longestNumberArray(e, path+"["+strconv.Itoa(i)+"]"))
		}
		if numbers {
			consider(path, len(x))
		}
	}
	return best, n
}
