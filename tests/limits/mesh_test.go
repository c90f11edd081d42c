package limits

import (
	"bufio"
	"flag"
	"math"
	"os"
	"path/filepath"
	"strconv"
	"testing"
	"time"

	"photonfarm/contract/rules"
	"photonfarm/contract/scene/scenetest"
	pb "photonfarm/proto/renderfarm/v1"
)

// writeGrid writes an OBJ mesh of a flat grid of at most triangles triangles (two a
// square cell) spanning [-1, 1]² at z = 0, and returns its path and its vertex and
// triangle counts.
func writeGrid(t *testing.T, triangles uint64) (path string, vertices, faces uint64) {
	t.Helper()
	n := uint64(math.Sqrt(float64(triangles / 2)))
	m := triangles / (2 * n)
	path = filepath.Join(t.TempDir(), "grid.obj")
	f, err := os.Create(path)
	if err != nil {
		t.Fatal(err)
	}
	w := bufio.NewWriterSize(f, 1<<20)
	var line []byte
	for j := uint64(0); j <= m; j++ {
		for i := uint64(0); i <= n; i++ {
			line = append(line[:0], "v "...)
			line = strconv.AppendFloat(line, 2*float64(i)/float64(n)-1, 'g', 7, 64)
			line = append(line, ' ')
			line = strconv.AppendFloat(line, 2*float64(j)/float64(m)-1, 'g', 7, 64)
			line = append(line, " 0\n"...)
			w.Write(line)
		}
	}
	at := func(i, j uint64) uint64 { return j*(n+1) + i + 1 }
	for j := uint64(0); j < m; j++ {
		for i := uint64(0); i < n; i++ {
			a, b, c, d := at(i, j), at(i+1, j), at(i+1, j+1), at(i, j+1)
			for _, tri := range [2][3]uint64{{a, b, c}, {a, c, d}} {
				line = append(line[:0], 'f')
				for _, v := range tri {
					line = append(line, ' ')
					line = strconv.AppendUint(line, v, 10)
				}
				w.Write(append(line, '\n'))
			}
		}
	}
	if err := w.Flush(); err != nil {
		t.Fatal(err)
	}
	if err := f.Close(); err != nil {
		t.Fatal(err)
	}
	return path, (n + 1) * (m + 1), 2 * n * m
}

var meshTriangles = flag.Uint64("limits.mesh-triangles", 0, "triangles of the mesh of TestMeshAtTheTriangleCapRenders (0: the cap with -limits.full, else 200,000)")

// TestMeshAtTheTriangleCapRenders renders a mesh file of the most triangles a mesh may
// have (max_mesh_triangles; reduced: 200,000) and logs what the worker's memory peaked
// at, per triangle: parsing the file and building Embree's BVH.
func TestMeshAtTheTriangleCapRenders(t *testing.T) {
	limit := rules.Scene.GetMaxMeshTriangles()
	n := size(limit, uint64(200_000))
	if *meshTriangles != 0 {
		n = *meshTriangles
	}
	path, vertices, faces := writeGrid(t, n)
	st, err := os.Stat(path)
	if err != nil {
		t.Fatal(err)
	}
	t.Logf("mesh: %d vertices, %d triangles (cap %d), %s", vertices, faces, limit, mb(uint64(st.Size())))
	r := newRun(t)
	digest, err := r.f.Client.UploadFile(ctx(t, 10*time.Minute), path)
	if err != nil {
		t.Fatal(err)
	}
	sc := scenetest.Valid(16, 16)
	sc.Shapes = append(sc.Shapes, &pb.Shape{Name: "grid", Material: "white",
		Geometry: &pb.Shape_Mesh{Mesh: &pb.MeshFile{Path: "grid.obj", Digest: digest}}})
	sc.Photons = &pb.PhotonMapping{GlobalPhotons: 1000, PhotonsPerShard: 1000}
	r.render(sc, 30*time.Minute)
	peak := r.worker().PeakRSS(t)
	t.Logf("worker: %.0f bytes of peak RSS a triangle", float64(peak)/float64(faces))
	r.taskTimes()
}
