package assets_test

import (
	"bytes"
	"context"
	"errors"
	"io"
	"strings"
	"testing"

	"photonfarm/contract/assets"
)

func fromBytes(b []byte) assets.Opener {
	return func() (io.ReadCloser, error) { return io.NopCloser(bytes.NewReader(b)), nil }
}

const triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"

func TestCheckOBJCountsAndBounds(t *testing.T) {
	obj := "v -1 2 -3\nv 4 -5 6\nv 0 0 0\nv 1 1 1\nf 1 2 3 4\nf 4 3 2\n"
	m, err := assets.CheckOBJ(context.Background(), fromBytes([]byte(obj)), assets.SceneLimits())
	if err != nil {
		t.Fatal(err)
	}
	want := assets.Mesh{Vertices: 4, Triangles: 3, Min: [3]float64{-1, -5, -3}, Max: [3]float64{4, 2, 6}}
	if m != want {
		t.Errorf("mesh = %+v, want %+v", m, want)
	}
}

func TestCheckOBJLimits(t *testing.T) {
	lim := assets.Limits{MaxBytes: uint64(len(triangle)), MaxVertices: 3, MaxTriangles: 1, MaxLineBytes: 1 << 16}
	for _, tc := range []struct {
		name, obj string
		lim       assets.Limits
		want      string // "" accepts
	}{
		{"at every limit", triangle, lim, ""},
		{"one byte too many", triangle + "\n", lim, "line 5: the file is larger than the limit of 32 bytes"},
		{"a vertex too many", "v 0 0 0\n" + triangle, assets.Limits{MaxBytes: 100, MaxVertices: 3, MaxTriangles: 1, MaxLineBytes: 1 << 16},
			"line 4: the mesh has more than 3 vertices (the limit of one mesh)"},
		{"a triangle too many", triangle + "f 3 2 1\n", assets.Limits{MaxBytes: 100, MaxVertices: 3, MaxTriangles: 1, MaxLineBytes: 1 << 16},
			"line 5: the mesh has more than 1 triangle (the limit of one mesh)"},
		{"a quad past the triangle limit", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n",
			assets.Limits{MaxBytes: 100, MaxVertices: 4, MaxTriangles: 1, MaxLineBytes: 1 << 16}, "line 5: the mesh has more than 1 triangle"},
		{"an empty file", "", lim, "line 1: the mesh has no triangles"},
	} {
		_, err := assets.CheckOBJ(context.Background(), fromBytes([]byte(tc.obj)), tc.lim)
		switch {
		case tc.want == "" && err != nil:
			t.Errorf("%s: refused: %v", tc.name, err)
		case tc.want != "" && (err == nil || !strings.HasPrefix(err.Error(), tc.want)):
			t.Errorf("%s: got %v, want %q", tc.name, err, tc.want)
		}
	}
}

// A reader that never ends (a mesh path naming /dev/zero's like, a pipe): the size bound
// and the context stop it.
type endless struct{ b byte }

func (e endless) Read(p []byte) (int, error) {
	for i := range p {
		p[i] = e.b
	}
	return len(p), nil
}
func (endless) Close() error { return nil }

func TestCheckOBJStopsOnEndlessInput(t *testing.T) {
	lim := assets.Limits{MaxBytes: 1 << 20, MaxVertices: 10, MaxTriangles: 10, MaxLineBytes: 1 << 16}
	zeros := func() (io.ReadCloser, error) { return endless{0}, nil }
	if _, err := assets.CheckOBJ(context.Background(), zeros, lim); err == nil || !strings.Contains(err.Error(), "line 1: contains a NUL byte") {
		t.Errorf("endless zeros: %v, want a NUL byte on line 1", err)
	}
	newlines := func() (io.ReadCloser, error) { return endless{'\n'}, nil }
	if _, err := assets.CheckOBJ(context.Background(), newlines, lim); err == nil || !strings.Contains(err.Error(), "larger than the limit") {
		t.Errorf("endless blank lines: %v, want the size limit", err)
	}
	ctx, cancel := context.WithCancel(context.Background())
	cancel()
	spaces := func() (io.ReadCloser, error) { return endless{' '}, nil }
	if _, err := assets.CheckOBJ(ctx, spaces, assets.SceneLimits()); !errors.Is(err, context.Canceled) {
		t.Errorf("cancelled: %v, want context.Canceled", err)
	}
}

func TestCheckOBJReportsTheOpenersError(t *testing.T) {
	gone := errors.New("blob gone")
	_, err := assets.CheckOBJ(context.Background(), func() (io.ReadCloser, error) { return nil, gone }, assets.SceneLimits())
	if !errors.Is(err, gone) {
		t.Errorf("got %v, want the opener's error", err)
	}
}

func TestCheckOBJReportsTheFirstBadLine(t *testing.T) {
	// Line 2 names a vertex the file lacks; line 4 is not text: line 2 comes first,
	// though the first pass stops at line 4.
	obj := "v 0 0 0\nf 1 2 9\nv 1 0 0\nv 0 1\x00 0\nf 1 2 3\n"
	_, err := assets.CheckOBJ(context.Background(), fromBytes([]byte(obj)), assets.SceneLimits())
	if err == nil || err.Error() != "line 2: face refers to vertex 9 but the file has 2 vertices" {
		t.Errorf("got %v", err)
	}
}

func TestCheckOBJLongLineOfMultibyteTextIsTooLongNotGarbage(t *testing.T) {
	// The line is cut at the buffer inside a two-byte character.
	obj := "# " + strings.Repeat("é", int(assets.SceneLimits().MaxLineBytes)) + "\n" + triangle
	_, err := assets.CheckOBJ(context.Background(), fromBytes([]byte(obj)), assets.SceneLimits())
	if err == nil || err.Error() != "line 1: is longer than 65536 bytes" {
		t.Errorf("got %v", err)
	}
}
