package importer_test

import (
	"bytes"
	"context"
	"encoding/binary"
	"hash/crc32"
	"math"
	"os"
	"path/filepath"
	"strings"
	"testing"
	"time"

	"github.com/qmuntal/gltf"
	"github.com/qmuntal/gltf/modeler"

	"photonfarm/client/importer"
	"photonfarm/client/importer/importertest"
)

// pngHeader is a PNG whose header declares w x h pixels and that has no pixels.
func pngHeader(w, h uint32) []byte {
	ihdr := make([]byte, 17)
	copy(ihdr, "IHDR")
	binary.BigEndian.PutUint32(ihdr[4:], w)
	binary.BigEndian.PutUint32(ihdr[8:], h)
	ihdr[12], ihdr[13] = 8, 6
	var b bytes.Buffer
	b.WriteString("\x89PNG\r\n\x1a\n")
	binary.Write(&b, binary.BigEndian, uint32(13))
	b.Write(ihdr)
	binary.Write(&b, binary.BigEndian, crc32.ChecksumIEEE(ihdr))
	return b.Bytes()
}

// TestBadModelsAreRefusedNamingWhatIsWrong: each broken model fails the import, quickly,
// with an error naming the file and what is wrong, and writes no scene.
func TestBadModelsAreRefusedNamingWhatIsWrong(t *testing.T) {
	for _, tt := range []struct {
		name, file, want string
		// break_ changes the model before it is saved; bytes changes the saved file.
		break_ func(t *testing.T, doc *gltf.Document)
		bytes  func(b []byte) []byte
	}{
		{name: "truncated glb", file: "m.glb", want: "not a glTF file this farm can read",
			bytes: func(b []byte) []byte { return b[:len(b)/2] }},
		{name: "buffer shorter than its accessor", file: "m.glb", want: "a buffer shorter than its accessor",
			break_: func(t *testing.T, doc *gltf.Document) { doc.Accessors[0].Count = 400 }},
		{name: "index out of range", file: "m.glb", want: "index 9 (accessor 4, element 2) is out of range: the primitive has 4 vertices",
			break_: func(t *testing.T, doc *gltf.Document) {
				doc.Meshes[0].Primitives[0].Indices = gltf.Index(modeler.WriteIndices(doc, []uint16{0, 1, 9}))
			}},
		{name: "NaN position", file: "m.glb", want: "POSITION (accessor 0) element 1 is not finite",
			break_: func(t *testing.T, doc *gltf.Document) {
				// The x of the second position, in the buffer (its min and max stay finite).
				a := doc.Accessors[doc.Meshes[0].Primitives[0].Attributes[gltf.POSITION]]
				bv := doc.BufferViews[*a.BufferView]
				stride := max(bv.ByteStride, 12)
				binary.LittleEndian.PutUint32(doc.Buffers[bv.Buffer].Data[bv.ByteOffset+a.ByteOffset+stride:], math.Float32bits(float32(math.NaN())))
			}},
		{name: "an image that is not an image", file: "m.glb", want: "not an image this farm reads",
			break_: func(t *testing.T, doc *gltf.Document) {
				i, _ := modeler.WriteImage(doc, "fake", "image/png", strings.NewReader("this is not a picture"))
				doc.Textures[0].Source = gltf.Index(i)
			}},
		{name: "a 65536 x 65536 texture", file: "m.glb", want: "a png image of 65536x65536 pixels is larger than",
			break_: func(t *testing.T, doc *gltf.Document) {
				i, _ := modeler.WriteImage(doc, "huge", "image/png", bytes.NewReader(pngHeader(65536, 65536)))
				doc.Textures[0].Source = gltf.Index(i)
			}},
		{name: "an unsupported required extension", file: "m.gltf", want: "requires the extension KHR_draco_mesh_compression",
			break_: func(t *testing.T, doc *gltf.Document) {
				doc.ExtensionsUsed = append(doc.ExtensionsUsed, "KHR_draco_mesh_compression")
				doc.ExtensionsRequired = []string{"KHR_draco_mesh_compression"}
			}},
		{name: "10,000 nodes deep", file: "m.gltf", want: "nodes nest more than 256 deep",
			break_: func(t *testing.T, doc *gltf.Document) {
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
		{name: "a node that is its own ancestor", file: "m.gltf", want: "node 0 has two parents or is its own ancestor",
			break_: func(t *testing.T, doc *gltf.Document) { doc.Nodes[1].Children = []int{0} }},
	} {
		t.Run(tt.name, func(t *testing.T) {
			doc := importertest.Model(t)
			if tt.break_ != nil {
				tt.break_(t, doc)
			}
			path := importertest.Save(t, doc, tt.file)
			if tt.bytes != nil {
				b, _ := os.ReadFile(path)
				os.WriteFile(path, tt.bytes(b), 0o644)
			}
			out := t.TempDir()
			start := time.Now()
			_, err := importer.Import(context.Background(), path, out, importer.Options{})
			if err == nil || !strings.Contains(err.Error(), tt.want) || !strings.HasPrefix(err.Error(), path+": ") {
				t.Fatalf("Import = %v, want an error naming %s and containing %q", err, path, tt.want)
			}
			if took := time.Since(start); took > 5*time.Second {
				t.Errorf("refusing took %v", took)
			}
			if entries, _ := filepath.Glob(filepath.Join(out, "*.json")); len(entries) != 0 {
				t.Errorf("a scene was written: %v", entries)
			}
		})
	}
}

// TestModelFilesMustBeRegularFilesInTheModelsFolder: a glTF's buffers and images, and an
// OBJ's MTL files and textures, are read only from its folder, only as regular files.
func TestModelFilesMustBeRegularFilesInTheModelsFolder(t *testing.T) {
	dir := t.TempDir()
	os.WriteFile(filepath.Join(t.TempDir(), "outside.bin"), []byte("x"), 0o644)
	os.Symlink("/etc/passwd", filepath.Join(dir, "link.bin"))
	os.Mkdir(filepath.Join(dir, "folder.bin"), 0o755)
	for _, name := range []string{"../outside.bin", "/etc/passwd", "link.bin", "folder.bin"} {
		if _, err := importer.ReadModelFile(dir, name); err == nil {
			t.Errorf("reading %q from the model's folder succeeded", name)
		}
	}
}
