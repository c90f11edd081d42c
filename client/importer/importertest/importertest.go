// Package importertest builds the small models the importer's tests and the farm's
// end-to-end tests import: a glTF document (saved as .glb, or .gltf with embedded or
// external buffers) and an OBJ with its MTL file and texture.
package importertest

import (
	"bytes"
	"fmt"
	"image"
	"image/color"
	"image/png"
	"math"
	"os"
	"path/filepath"
	"strings"
	"testing"

	"github.com/qmuntal/gltf"
	"github.com/qmuntal/gltf/ext/lightspunctual"
	"github.com/qmuntal/gltf/modeler"
)

// Checker is a side x side PNG of opaque white and fully transparent texels, alternating:
// an alpha mask cuts holes where the filtered alpha falls below its cutoff (round ones
// about the transparent texels when a few texels are magnified and the cutoff is low).
func Checker(t testing.TB, side int) []byte {
	t.Helper()
	img := image.NewNRGBA(image.Rect(0, 0, side, side))
	for y := range side {
		for x := range side {
			if (x+y)%2 == 0 {
				img.SetNRGBA(x, y, color.NRGBA{R: 255, G: 255, B: 255, A: 255})
			}
		}
	}
	var b bytes.Buffer
	if err := png.Encode(&b, img); err != nil {
		t.Fatal(err)
	}
	return b.Bytes()
}

// Model is a small glTF document: one quad mesh, textured with a 4 x 4 Checker and
// alpha-masked, placed by two nodes (one a child of the other), a camera at z 10 looking
// down -z, and a point light at (0, 5, 5) in front of the quads.
func Model(t testing.TB) *gltf.Document {
	t.Helper()
	doc := gltf.NewDocument()
	imageIndex, err := modeler.WriteImage(doc, "checker", "image/png", bytes.NewReader(Checker(t, 4)))
	if err != nil {
		t.Fatal(err)
	}
	doc.Textures = []*gltf.Texture{{Source: gltf.Index(imageIndex)}}
	doc.Materials = []*gltf.Material{{
		Name: "painted",
		PBRMetallicRoughness: &gltf.PBRMetallicRoughness{
			BaseColorFactor:  &[4]float64{0.8, 0.5, 0.2, 1},
			BaseColorTexture: &gltf.TextureInfo{Index: 0},
			MetallicFactor:   gltf.Float(0.25),
			RoughnessFactor:  gltf.Float(0.5),
		},
		AlphaMode:   gltf.AlphaMask,
		AlphaCutoff: gltf.Float(0.3),
	}}
	attrs, err := modeler.WritePrimitiveAttributes(doc,
		modeler.PrimitiveAttribute{Name: gltf.POSITION, Data: [][3]float32{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}},
		modeler.PrimitiveAttribute{Name: gltf.NORMAL, Data: [][3]float32{{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}}},
		modeler.PrimitiveAttribute{Name: gltf.TEXCOORD_0, Data: [][2]float32{{0, 1}, {1, 1}, {1, 0}, {0, 0}}})
	if err != nil {
		t.Fatal(err)
	}
	doc.Meshes = []*gltf.Mesh{{Name: "quad", Primitives: []*gltf.Primitive{{
		Attributes: attrs, Indices: gltf.Index(modeler.WriteIndices(doc, []uint16{0, 1, 2, 0, 2, 3})), Material: gltf.Index(0),
	}}}}
	doc.Cameras = []*gltf.Camera{{Perspective: &gltf.Perspective{Yfov: math.Pi / 4, AspectRatio: gltf.Float(2)}}}
	doc.Extensions = gltf.Extensions{lightspunctual.ExtensionName: map[string]any{"lights": lightspunctual.Lights{
		{Type: lightspunctual.TypePoint, Color: &[3]float64{1, 1, 1}, Intensity: gltf.Float(683)},
	}}}
	doc.ExtensionsUsed = []string{lightspunctual.ExtensionName}
	doc.Nodes = []*gltf.Node{
		{Name: "first", Mesh: gltf.Index(0), Children: []int{1}, Translation: [3]float64{2, 0, 0}, Rotation: gltf.DefaultRotation, Scale: gltf.DefaultScale, Matrix: gltf.DefaultMatrix},
		{Name: "second", Mesh: gltf.Index(0), Translation: [3]float64{0, 3, 0}, Rotation: gltf.DefaultRotation, Scale: [3]float64{2, 2, 2}, Matrix: gltf.DefaultMatrix},
		{Name: "eye", Camera: gltf.Index(0), Translation: [3]float64{0, 0, 10}, Rotation: gltf.DefaultRotation, Scale: gltf.DefaultScale, Matrix: gltf.DefaultMatrix},
		{Name: "lamp", Translation: [3]float64{0, 5, 5}, Rotation: gltf.DefaultRotation, Scale: gltf.DefaultScale, Matrix: gltf.DefaultMatrix,
			Extensions: gltf.Extensions{lightspunctual.ExtensionName: map[string]int{"light": 0}}},
	}
	doc.Scenes = []*gltf.Scene{{Nodes: []int{0, 2, 3}}}
	doc.Scene = gltf.Index(0)
	return doc
}

// ExternalBuffers names each buffer of doc a file of its own (stem-0.bin, ...), so that
// Save writes a .gltf with its buffers beside it instead of embedding them as data: URIs.
func ExternalBuffers(doc *gltf.Document, stem string) {
	for i, b := range doc.Buffers {
		b.URI = fmt.Sprintf("%s-%d.bin", stem, i)
	}
}

// Save writes doc into a new folder as name: a glTF binary for a .glb, else a .gltf whose
// buffers without a URI are embedded as data: URIs (see ExternalBuffers). It returns the
// file's path.
func Save(t testing.TB, doc *gltf.Document, name string) string {
	t.Helper()
	path := filepath.Join(t.TempDir(), name)
	var err error
	if strings.HasSuffix(name, ".glb") {
		err = gltf.SaveBinary(doc, path)
	} else {
		err = gltf.Save(doc, path)
	}
	if err != nil {
		t.Fatal(err)
	}
	return path
}

// QuadsOBJ is an OBJ of two faces of two materials (look.mtl's painted and glass), with
// texture coordinates and a normal.
const QuadsOBJ = `# two quads, two materials
mtllib look.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vn 0 0 1
usemtl painted
f 1/1/1 2/2/1 3/3/1 4/4/1
usemtl glass
f 5 6 2
`

// LookMTL is QuadsOBJ's look.mtl: a painted material textured with paint.png, and glass.
const LookMTL = `newmtl painted
Kd 0.5 0.25 1
Ns 98
Ke 0 0 0
map_Kd -s 2 2 1 paint.png
newmtl glass
illum 7
Ni 1.45
Tf 0.9 0.9 1
`

// WriteOBJ writes QuadsOBJ as quads.obj into a new folder, with look.mtl and paint.png (a
// 2 x 2 Checker) beside it when mtl is set, and returns the OBJ's path.
func WriteOBJ(t testing.TB, mtl bool) string {
	t.Helper()
	dir := t.TempDir()
	files := map[string][]byte{"quads.obj": []byte(QuadsOBJ)}
	if mtl {
		files["look.mtl"], files["paint.png"] = []byte(LookMTL), Checker(t, 2)
	}
	for name, data := range files {
		if err := os.WriteFile(filepath.Join(dir, name), data, 0o644); err != nil {
			t.Fatal(err)
		}
	}
	return filepath.Join(dir, "quads.obj")
}
