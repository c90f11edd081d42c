package importer_test

import (
	"context"
	"os"
	"path/filepath"
	"strings"
	"testing"
	"time"

	"photonfarm/client/importer"
	"photonfarm/client/importer/importertest"
)

// TestBadModelsAreRefusedNamingWhatIsWrong: each broken model fails the import, quickly,
// with an error naming the file and what is wrong, and writes no scene.
func TestBadModelsAreRefusedNamingWhatIsWrong(t *testing.T) {
	for _, tt := range importertest.BadModels {
		t.Run(tt.Name, func(t *testing.T) {
			path := tt.Write(t)
			out := t.TempDir()
			start := time.Now()
			_, err := importer.Import(context.Background(), path, out, importer.Options{})
			if err == nil || !strings.Contains(err.Error(), tt.Want) || !strings.HasPrefix(err.Error(), path+": ") {
				t.Fatalf("Import = %v, want an error naming %s and containing %q", err, path, tt.Want)
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
