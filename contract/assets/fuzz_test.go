package assets_test

import (
	"context"
	"errors"
	"os"
	"path/filepath"
	"testing"

	"photonfarm/contract/assets"
)

// FuzzCheckOBJ: whatever the bytes, the checker answers (no panic, no hang) with a mesh
// or an *Error naming a line of the input; seeded with the shared vectors.
func FuzzCheckOBJ(f *testing.F) {
	files, _ := filepath.Glob(filepath.Join(vectorDir, "*.obj"))
	for _, file := range files {
		if b, err := os.ReadFile(file); err == nil && len(b) < 4096 {
			f.Add(b)
		}
	}
	lim := assets.Limits{MaxBytes: 1 << 16, MaxVertices: 1000, MaxTriangles: 1000, MaxLineBytes: 1 << 16}
	f.Fuzz(func(t *testing.T, data []byte) {
		m, err := assets.CheckOBJ(context.Background(), fromBytes(data), lim)
		var e *assets.Error
		switch {
		case err == nil && (m.Triangles == 0 || m.Triangles > lim.MaxTriangles || m.Vertices > lim.MaxVertices):
			t.Fatalf("accepted %+v", m)
		case err != nil && !errors.As(err, &e):
			t.Fatalf("error %v is not an *assets.Error", err)
		case err != nil && (e.Line < 1 || e.Line > 1+countLines(data)):
			t.Fatalf("error %v names a line outside the input's %d", err, countLines(data))
		}
	})
}

func countLines(b []byte) int {
	n := 0
	for _, c := range b {
		if c == '\n' {
			n++
		}
	}
	return n
}
