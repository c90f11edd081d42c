package main

import (
	"bytes"
	"encoding/binary"
	"fmt"
	"math"

	"photonfarm/contract/assets"
	"photonfarm/contract/assets/assetstest"
	"photonfarm/contract/rules"
	"photonfarm/tests/vectors/vectorfiles"
)

// farmCase is one farm mesh vector (the fields of vectorfiles.BinaryCase).
type farmCase vectorfiles.BinaryCase

func encode(m *assets.MeshData) []byte {
	var b bytes.Buffer
	if err := assets.EncodeFarmMesh(&b, m); err != nil {
		panic(err) // the cases' meshes are well formed
	}
	return b.Bytes()
}

// Offsets of quad's sections.
const (
	normals   = 32 + 48
	texcoords = normals + 48
	tangents  = texcoords + 32
	indices   = tangents + 64
)

func put64(b []byte, at int, v uint64) []byte {
	b = bytes.Clone(b)
	binary.LittleEndian.PutUint64(b[at:], v)
	return b
}

// cases lists the farm mesh vectors.
func cases() []farmCase {
	good := encode(assetstest.Quad())
	bare := encode(&assets.MeshData{Positions: assetstest.Quad().Positions, Indices: assetstest.Quad().Indices})
	onlyTexCoords := assetstest.Quad()
	onlyTexCoords.Normals, onlyTexCoords.Tangents = nil, nil
	mirrored := assetstest.Quad()
	for i := 3; i < len(mirrored.Tangents); i += 4 {
		mirrored.Tangents[i] = -1
	}
	unnormalised := assetstest.Quad()
	unnormalised.Normals = []float32{0, 0, 3, 0, 0, 0, 0, 0.5, 0.5, 0, 0, 1} // a zero normal is "none here"
	degenerate := assetstest.Quad()
	degenerate.Indices = append(degenerate.Indices, 1, 1, 2)
	nan, inf := float32(math.NaN()), float32(math.Inf(1))
	// The counts at the scene limits; with every section, the most vertices and triangles
	// a mesh may have make a file larger than an asset may be.
	maxV, maxT := rules.Scene.GetMaxMeshVertices(), rules.Scene.GetMaxMeshTriangles()
	implied := 32 + maxV*(12+12+8+16) + maxT*12
	if implied <= rules.Scene.GetMaxAssetBytes() {
		panic("the asset limit no longer refuses a header at the mesh limits: choose another case")
	}
	return []farmCase{
		{"accept-quad-with-every-section", good, 0, ""},
		{"accept-quad-of-positions-only", bare, 0, ""},
		{"accept-quad-with-texture-coordinates-only", encode(onlyTexCoords), 0, ""},
		{"accept-tangents-with-w-minus-1", encode(mirrored), 0, ""},
		{"accept-normals-of-any-length-and-a-zero-normal", encode(unnormalised), 0, ""},
		{"accept-degenerate-triangle", encode(degenerate), 0, ""},
		{"accept-positions-at-max-magnitude", vectorfiles.Float32(vectorfiles.Float32(bare, 32, 1e12), 40, -1e12), 0, ""},

		{"refuse-short-header", good[:20], 20, "the file ends inside its 32-byte header"},
		{"refuse-no-magic", append([]byte("FARMMASH"), good[8:]...), 0, `not a farm mesh file (no "FARMMESH" magic)`},
		{"refuse-version-2", vectorfiles.Put32(good, 8, 2), 8, "version 2, but this farm reads version 1"},
		{"refuse-unknown-flag", vectorfiles.Put32(good, 12, 0x17), 12, "unknown flags 0x10"},
		{"refuse-no-vertices", put64(good, 16, 0), 16, "the mesh has no vertices"},
		{"refuse-too-many-vertices", put64(bare, 16, maxV+1), 16, fmt.Sprintf("%d vertices, more than the %d of one mesh", maxV+1, maxV)},
		{"refuse-no-triangles", put64(good, 24, 0), 24, "the mesh has no triangles"},
		{"refuse-too-many-triangles", put64(bare, 24, maxT+1), 24, fmt.Sprintf("%d triangles, more than the %d of one mesh", maxT+1, maxT)},
		{"refuse-header-implying-more-than-an-asset", put64(put64(good, 16, maxV), 24, maxT), 16, fmt.Sprintf("the header implies %d bytes, more than the %d of one asset", implied, rules.Scene.GetMaxAssetBytes())},
		{"refuse-nan-position", vectorfiles.Float32(good, 36, nan), 36, "position 1 is not finite"},
		{"refuse-position-out-of-range", vectorfiles.Float32(good, 32, 2e12), 32, "position 0's coordinate 1.999999991808e+12 is out of range: numbers are at most ±1e+12"},
		{"refuse-infinite-normal", vectorfiles.Float32(good, normals+8, inf), normals + 8, "normal 2 is not finite"},
		{"refuse-nan-texture-coordinate", vectorfiles.Float32(good, texcoords+4, nan), texcoords + 4, "texture coordinate 1 is not finite"},
		{"refuse-tangent-w-of-0.5", vectorfiles.Float32(good, tangents+12, 0.5), tangents + 12, "tangent 0's w is 0.5, not 1 or -1"},
		{"refuse-tangent-w-of-0", vectorfiles.Float32(good, tangents+28, 0), tangents + 28, "tangent 1's w is 0, not 1 or -1"},
		{"refuse-index-past-the-vertices", vectorfiles.Put32(good, indices+8, 4), indices + 8, "triangle 0 refers to vertex 4 but the mesh has 4 vertices"},
		{"refuse-file-cut-in-its-positions", good[:40], 40, "the file ends inside its positions"},
		{"refuse-file-cut-in-its-tangents", good[:tangents+2], tangents + 2, "the file ends inside its tangents"},
		{"refuse-file-cut-in-its-last-triangle", good[:len(good)-2], int64(len(good) - 2), "the file ends before its last triangle"},
		{"refuse-trailing-bytes", append(bytes.Clone(good), 0), int64(len(good)), "the file goes on past its last triangle"},
	}
}
