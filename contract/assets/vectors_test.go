package assets_test

import (
	"bufio"
	"context"
	"errors"
	"fmt"
	"io"
	"os"
	"path/filepath"
	"regexp"
	"strconv"
	"strings"
	"testing"

	"photonfarm/contract/assets"
)

// The mesh vectors are shared with the worker's loader tests: each OBJ file in
// tests/vectors/meshes has a first line that says what both sides must make of it,
// "# vector: accept" or "# vector: refuse line N: REASON" (the error names line N and
// contains REASON); each farm mesh file NAME.farmmesh has a sidecar NAME.farmmesh.vector
// whose line says "# vector: accept" or "# vector: refuse byte N: REASON".
const vectorDir = "../../tests/vectors/meshes"

var verdict = regexp.MustCompile(`^# vector: (?:(accept)|refuse line (\d+): (.+))$`)

var farmVerdict = regexp.MustCompile(`^# vector: (?:(accept)|refuse byte (\d+): (.+))\n$`)

func TestFarmMeshVectors(t *testing.T) {
	sidecarVectors(t, filepath.Join(vectorDir, "*.farmmesh"), func(file string) (int64, string, error) {
		mesh, err := assets.CheckFarmMesh(context.Background(), openFile(file), assets.SceneLimits())
		var e *assets.FarmMeshError
		if errors.As(err, &e) {
			return e.Offset, e.Reason, err
		}
		if err == nil && (mesh.Vertices == 0 || mesh.Triangles == 0) {
			err = fmt.Errorf("accepted as %+v, without vertices or triangles", mesh)
		}
		return -1, "", err
	})
}

// The farm grid vectors (tests/vectors/grids) are shared with the worker's reader the same
// way: NAME.farmgrid beside its NAME.farmgrid.vector.
func TestFarmGridVectors(t *testing.T) {
	sidecarVectors(t, "../../tests/vectors/grids/*.farmgrid", func(file string) (int64, string, error) {
		grid, err := assets.CheckFarmGrid(context.Background(), openFile(file), assets.SceneGridLimits())
		var e *assets.FarmGridError
		if errors.As(err, &e) {
			return e.Offset, e.Reason, err
		}
		if err == nil && !(grid.MaxDensity > 0) {
			err = fmt.Errorf("accepted as %+v, without a positive density", grid)
		}
		return -1, "", err
	})
}

// sidecarVectors runs check on every file glob matches and holds it to the verdict of the
// file's sidecar (FILE.vector): accepted (check returns no error), or refused with an
// assets.Refusal at the byte offset and with the reason the sidecar says (check returns
// the refusal's offset and reason, and the error).
func sidecarVectors(t *testing.T, glob string, check func(file string) (offset int64, reason string, err error)) {
	files, err := filepath.Glob(glob)
	if err != nil || len(files) == 0 {
		t.Fatalf("no vectors match %s: %v", glob, err)
	}
	for _, file := range files {
		t.Run(filepath.Base(file), func(t *testing.T) {
			sidecar, err := os.ReadFile(file + ".vector")
			if err != nil {
				t.Fatal(err)
			}
			m := farmVerdict.FindStringSubmatch(string(sidecar))
			if m == nil {
				t.Fatalf("%s.vector: %q is not \"# vector: accept\" or \"# vector: refuse byte N: REASON\"", file, sidecar)
			}
			offset, reason, err := check(file)
			if m[1] != "" {
				if err != nil {
					t.Fatalf("got %v; want it accepted", err)
				}
				return
			}
			want, _ := strconv.ParseInt(m[2], 10, 64)
			if offset != want || !strings.Contains(reason, m[3]) {
				t.Errorf("got %v, want a refusal at byte %d with %q", err, want, m[3])
			}
			var refusal assets.Refusal
			if !errors.As(err, &refusal) {
				t.Errorf("%v is not an assets.Refusal", err)
			}
		})
	}
}

func TestMeshVectors(t *testing.T) {
	files, err := filepath.Glob(filepath.Join(vectorDir, "*.obj"))
	if err != nil || len(files) == 0 {
		t.Fatalf("no OBJ vectors in %s: %v", vectorDir, err)
	}
	for _, file := range files {
		t.Run(filepath.Base(file), func(t *testing.T) {
			accept, line, reason := readVerdict(t, file)
			mesh, err := assets.CheckOBJ(context.Background(), openFile(file), assets.SceneLimits())
			if accept {
				if err != nil {
					t.Fatalf("refused: %v", err)
				}
				if mesh.Vertices == 0 || mesh.Triangles == 0 {
					t.Errorf("accepted as %+v, want vertices and triangles", mesh)
				}
				return
			}
			var e *assets.Error
			if !errors.As(err, &e) {
				t.Fatalf("got %v (mesh %+v), want a refusal of line %d: %s", err, mesh, line, reason)
			}
			if e.Line != line || !strings.Contains(e.Reason, reason) || !strings.HasPrefix(err.Error(), "line "+strconv.Itoa(line)+": ") {
				t.Errorf("refused with %q, want line %d and %q", err, line, reason)
			}
		})
	}
}

func readVerdict(t *testing.T, file string) (accept bool, line int, reason string) {
	t.Helper()
	f, err := os.Open(file)
	if err != nil {
		t.Fatal(err)
	}
	defer f.Close()
	first, err := bufio.NewReader(f).ReadString('\n')
	if err != nil && err != io.EOF {
		t.Fatal(err)
	}
	first = strings.TrimRight(first, "\r\n")
	// A vector whose line breaks are carriage returns alone has its verdict up to the first.
	first, _, _ = strings.Cut(first, "\r")
	m := verdict.FindStringSubmatch(first)
	if m == nil {
		t.Fatalf("first line %q is not \"# vector: accept\" or \"# vector: refuse line N: REASON\"", first)
	}
	if m[1] != "" {
		return true, 0, ""
	}
	n, _ := strconv.Atoi(m[2])
	return false, n, m[3]
}

func openFile(path string) assets.Opener {
	return func() (io.ReadCloser, error) { return os.Open(path) }
}
