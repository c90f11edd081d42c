package assets_test

import (
	"bytes"
	"context"
	"errors"
	"io"
	"testing"

	"photonfarm/contract/assets"
	"photonfarm/contract/assets/assetstest"
)

func encode(t *testing.T, m *assets.MeshData) []byte {
	t.Helper()
	var b bytes.Buffer
	if err := assets.EncodeFarmMesh(&b, m); err != nil {
		t.Fatal(err)
	}
	return b.Bytes()
}

func check(b []byte) (assets.Mesh, error) {
	open := func() (io.ReadCloser, error) { return io.NopCloser(bytes.NewReader(b)), nil }
	return assets.CheckMesh(context.Background(), open, assets.SceneLimits())
}

func TestFarmMeshRoundTripCountsAndBounds(t *testing.T) {
	for _, m := range []*assets.MeshData{assetstest.Quad(), {Positions: assetstest.Quad().Positions, Indices: assetstest.Quad().Indices}} {
		b := encode(t, m)
		if want := 32 + len(m.Positions)*4 + len(m.Normals)*4 + len(m.TexCoords)*4 + len(m.Tangents)*4 + len(m.Indices)*4; len(b) != want {
			t.Errorf("file of %d bytes, want %d", len(b), want)
		}
		got, err := check(b)
		if err != nil {
			t.Fatal(err)
		}
		if got.Vertices != 4 || got.Triangles != 2 || got.Min != [3]float64{0, 0, 0} || got.Max != [3]float64{1, 1, 0} {
			t.Errorf("CheckMesh = %+v, want 4 vertices, 2 triangles in the unit square", got)
		}
	}
}

func TestEncodeRefusesArraysThatDoNotFit(t *testing.T) {
	m := assetstest.Quad()
	m.TexCoords = m.TexCoords[:6]
	if err := assets.EncodeFarmMesh(io.Discard, m); err == nil {
		t.Error("EncodeFarmMesh accepted 3 texture coordinates for 4 vertices")
	}
}

func TestCheckMeshStillReadsOBJ(t *testing.T) {
	if m, err := check([]byte("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")); err != nil || m.Triangles != 1 {
		t.Errorf("CheckMesh of an OBJ = %+v, %v", m, err)
	}
}

// TestFarmMeshLimits: files past small limits are refused where the worker's reader
// refuses them (worker/scene/farm_mesh_test.cpp has the same cases).
func TestFarmMeshLimits(t *testing.T) {
	good := encode(t, assetstest.Quad()) // 248 bytes
	limits := func(bytes, vertices, triangles uint64) assets.Limits {
		return assets.Limits{MaxBytes: bytes, MaxVertices: vertices, MaxTriangles: triangles, MaxLineBytes: 100}
	}
	for _, tt := range []struct {
		name   string
		file   []byte
		lim    assets.Limits
		offset int64
		reason string
	}{
		{"a header past the byte limit", good, limits(247, 10, 10), 16, "the header implies 248 bytes, more than the 247 of one asset"},
		{"a file exactly at the limit", good, limits(248, 10, 10), 0, ""},
		{"a byte past the limit", append(bytes.Clone(good), 'x'), limits(248, 10, 10), 248, "the file is larger than the limit of one asset"},
		{"a byte past the header", good, limits(20, 10, 10), 20, "the file is larger than the limit of one asset"},
		{"a byte past the limit, below the header's size", append(bytes.Clone(good), 'x'), limits(250, 10, 10), 248, "the file goes on past its last triangle"},
		{"too many vertices", good, limits(1000, 3, 10), 16, "4 vertices, more than the 3 of one mesh"},
		{"too many triangles", good, limits(1000, 10, 1), 24, "2 triangles, more than the 1 of one mesh"},
	} {
		t.Run(tt.name, func(t *testing.T) {
			open := func() (io.ReadCloser, error) { return io.NopCloser(bytes.NewReader(tt.file)), nil }
			_, err := assets.CheckFarmMesh(context.Background(), open, tt.lim)
			if tt.reason == "" {
				if err != nil {
					t.Fatalf("refused: %v", err)
				}
				return
			}
			var bad *assets.FarmMeshError
			if !errors.As(err, &bad) || bad.Offset != tt.offset || bad.Reason != tt.reason {
				t.Errorf("CheckFarmMesh = %v, want byte %d: %s", err, tt.offset, tt.reason)
			}
		})
	}
}
