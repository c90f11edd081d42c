package importer

import (
	"bytes"
	"fmt"
	"os"
	"path/filepath"
	"regexp"
	"strings"

	"google.golang.org/protobuf/encoding/protojson"

	"photonfarm/contract/assets"
	pb "photonfarm/proto/renderfarm/v1"
)

// writer puts an import's files in its folder under names of its own choosing.
type writer struct {
	dir   string
	names map[string]bool
	wrote []string
}

var unsafeName = regexp.MustCompile(`[^A-Za-z0-9._-]+`)

// name returns a fresh relative path folder/stem.ext made of safe characters.
func (w *writer) name(folder, stem, ext string) string {
	stem = strings.Trim(unsafeName.ReplaceAllString(stem, "-"), "-.")
	if len(stem) > 64 {
		stem = stem[:64]
	}
	if stem == "" {
		stem = "unnamed"
	}
	rel := folder + "/" + stem + ext
	for n := 2; w.names[rel]; n++ {
		rel = fmt.Sprintf("%s/%s-%d%s", folder, stem, n, ext)
	}
	w.names[rel] = true
	return rel
}

// file writes data under folder/stem.ext and returns its relative path.
func (w *writer) file(folder, stem, ext string, data []byte) (string, error) {
	rel := w.name(folder, stem, ext)
	p := filepath.Join(w.dir, filepath.FromSlash(rel))
	if err := os.MkdirAll(filepath.Dir(p), 0o755); err != nil {
		return "", err
	}
	if err := os.WriteFile(p, data, 0o644); err != nil {
		return "", err
	}
	w.wrote = append(w.wrote, rel)
	return rel, nil
}

// mesh writes m as a farm mesh file and returns its relative path.
func (w *writer) mesh(stem string, m *assets.MeshData) (string, error) {
	var b bytes.Buffer
	if err := assets.EncodeFarmMesh(&b, m); err != nil {
		return "", err
	}
	return w.file("meshes", stem, ".fmesh", b.Bytes())
}

// WriteScene writes s as the scene file path (protobuf's JSON mapping, indented).
func WriteScene(path string, s *pb.Scene) error {
	data, err := protojson.MarshalOptions{Multiline: true, Indent: "  "}.Marshal(s)
	if err != nil {
		return err
	}
	return os.WriteFile(path, append(data, '\n'), 0o644)
}
