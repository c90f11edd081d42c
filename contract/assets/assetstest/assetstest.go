// Package assetstest holds the asset files tests and the vector generators start from.
package assetstest

import "photonfarm/contract/assets"

// Quad is a unit square of two triangles with every optional section of a farm mesh file:
// normals, texture coordinates (v down: the top edge at v = 0) and tangents.
func Quad() *assets.MeshData {
	return &assets.MeshData{
		Positions: []float32{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0},
		Normals:   []float32{0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1},
		TexCoords: []float32{0, 1, 1, 1, 1, 0, 0, 0},
		Tangents:  []float32{1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1},
		Indices:   []uint32{0, 1, 2, 0, 2, 3},
	}
}
