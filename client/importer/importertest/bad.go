package importertest

import (
	"bytes"
	"encoding/binary"
	"math"
	"os"
	"strings"
	"testing"

	"github.com/qmuntal/gltf"
	"github.com/qmuntal/gltf/modeler"

	"photonfarm/contract/assets/assetstest"
)

// BadModel is Model broken in one way, and what refusing it must say.
type BadModel struct {
	Name, File, Want string // what is wrong; the file name it is saved as; the refusal's words
	// Break changes the model before it is saved; Cut changes the saved file.
	Break func(doc *gltf.Document)
	Cut   func(b []byte) []byte
}

// Write saves the broken model into a new folder and returns its path.
func (m BadModel) Write(t testing.TB) string {
	t.Helper()
	doc := Model(t)
	if m.Break != nil {
		m.Break(doc)
	}
	path := Save(t, doc, m.File)
	if m.Cut != nil {
		b, err := os.ReadFile(path)
		if err != nil {
			t.Fatal(err)
		}
		if err := os.WriteFile(path, m.Cut(b), 0o644); err != nil {
			t.Fatal(err)
		}
	}
	return path
}

// BadModels are the broken glTF models of issue 13's acceptance (a truncated .glb, a
// buffer shorter than its accessor, an index out of range, a NaN position, an image that
// is not an image, a 65,536 x 65,536 texture, an unsupported required extension, 10,000
// nodes deep) and a cycle in the node graph.
var BadModels = []BadModel{
	{Name: "truncated glb", File: "m.glb", Want: "not a glTF file this farm can read",
		Cut: func(b []byte) []byte { return b[:len(b)/2] }},
	{Name: "buffer shorter than its accessor", File: "m.glb", Want: "a buffer shorter than its accessor",
		Break: func(doc *gltf.Document) { doc.Accessors[0].Count = 400 }},
	{Name: "index out of range", File: "m.glb", Want: "index 9 (accessor 4, element 2) is out of range: the primitive has 4 vertices",
		Break: func(doc *gltf.Document) {
			doc.Meshes[0].Primitives[0].Indices = gltf.Index(modeler.WriteIndices(doc, []uint16{0, 1, 9}))
		}},
	{Name: "NaN position", File: "m.glb", Want: "POSITION (accessor 0) element 1 is not finite",
		Break: func(doc *gltf.Document) {
			// The x of the second position, in the buffer (its min and max stay finite).
			a := doc.Accessors[doc.Meshes[0].Primitives[0].Attributes[gltf.POSITION]]
			bv := doc.BufferViews[*a.BufferView]
			stride := max(bv.ByteStride, 12)
			binary.LittleEndian.PutUint32(doc.Buffers[bv.Buffer].Data[bv.ByteOffset+a.ByteOffset+stride:], math.Float32bits(float32(math.NaN())))
		}},
	{Name: "an image that is not an image", File: "m.glb", Want: "not an image this farm reads",
		Break: func(doc *gltf.Document) {
			i, _ := modeler.WriteImage(doc, "fake", "image/png", strings.NewReader("this is not a picture"))
			doc.Textures[0].Source = gltf.Index(i)
		}},
	{Name: "a 65536 x 65536 texture", File: "m.glb", Want: "a png image of 65536x65536 pixels is larger than",
		Break: func(doc *gltf.Document) {
			i, _ := modeler.WriteImage(doc, "huge", "image/png", bytes.NewReader(assetstest.PNGHeader(65536, 65536)))
			doc.Textures[0].Source = gltf.Index(i)
		}},
	{Name: "an unsupported required extension", File: "m.gltf", Want: "requires the extension KHR_draco_mesh_compression",
		Break: func(doc *gltf.Document) {
			doc.ExtensionsUsed = append(doc.ExtensionsUsed, "KHR_draco_mesh_compression")
			doc.ExtensionsRequired = []string{"KHR_draco_mesh_compression"}
		}},
	{Name: "10,000 nodes deep", File: "m.gltf", Want: "nodes nest more than 256 deep",
		Break: func(doc *gltf.Document) {
			base := len(doc.Nodes)
			for i := 0; i < 10000; i++ {
				n := &gltf.Node{Rotation: gltf.DefaultRotation, Scale: gltf.DefaultScale, Matrix: gltf.DefaultMatrix}
				if i+1 < 10000 {
					n.Children = []int{base + i + 1}
				}
				doc.Nodes = append(doc.Nodes, n)
			}
			doc.Scenes[0].Nodes = append(doc.Scenes[0].Nodes, base)
		}},
	{Name: "a node that is its own ancestor", File: "m.gltf", Want: "node 0 has two parents or is its own ancestor",
		Break: func(doc *gltf.Document) { doc.Nodes[1].Children = []int{0} }},
}
